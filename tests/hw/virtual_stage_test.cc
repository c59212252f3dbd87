// The whole no-hardware HIL path, for real: `motionblocks virtual-stage` runs the plant in a child process on
// an ephemeral loopback port; the HIL loop (UdpBoard + RunHilLoop, or the `motionblocks hil` command) runs the
// controller against it in real time. Checks: the HIL run reproduces the simulated run; a killed stage and
// dropped packets trigger the safe stop (and the stage's own watchdog zeroes its force).
// Timing tolerances are generous: the machine may be a loaded 2-core box running sanitizer builds.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"
#include "hw/board_registry.h"
#include "hw/hil_runner.h"
#include "hw/udp_board.h"
#include "hw/udp_socket.h"
#include "hw/virtual_stage.h"
#include "tests/alloc_counter.h"
#include "tests/hw/hil_test_util.h"

extern char** environ;

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A child process running the motionblocks binary with `args`, stdout and stderr to `log`.
class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& args, const fs::path& log) : log_(log) {
    std::vector<char*> argv;
    std::vector<std::string> storage = args;
    storage.insert(storage.begin(), MB_MOTIONBLOCKS_EXE);
    for (auto& a : storage) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    const int error = posix_spawn(&pid_, MB_MOTIONBLOCKS_EXE, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (error != 0) pid_ = -1;
  }
  ~ChildProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      Wait();
    }
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool started() const { return pid_ > 0; }
  void Signal(int signal) const { kill(pid_, signal); }
  /// Waits for the exit; returns the exit status (or 128 + signal).
  int Wait() {
    int status = 0;
    if (pid_ <= 0) return exit_code_;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return exit_code_;
  }
  /// Waits at most `timeout_s` for the exit; returns the exit status, or -2 after killing a child that did not end.
  int WaitFor(double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (pid_ > 0 && std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        return exit_code_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (pid_ <= 0) return exit_code_;
    kill(pid_, SIGKILL);
    Wait();
    return -2;
  }
  std::string Output() const { return ReadFile(log_); }
  /// Polls the output until it contains `text` or `timeout_s` passes.
  bool WaitForOutput(const std::string& text, double timeout_s) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      if (Output().find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

 private:
  fs::path log_;
  pid_t pid_ = -1;
  int exit_code_ = -1;
};

class VirtualStageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_virtual_stage_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Starts the virtual stage of the shipped HIL diagram on a free port; returns the port (0 on failure).
  std::uint16_t StartStage(std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"virtual-stage",
                                     (testing::HilDiagramDir() / "subsystems" / "plant.json").string(),
                                     "--io",
                                     (testing::HilDiagramDir() / "subsystems" / "hil_io.json").string(),
                                     "--port",
                                     "0"};
    args.insert(args.end(), extra.begin(), extra.end());
    stage_ = std::make_unique<ChildProcess>(args, dir_ / "stage.log");
    const std::string marker = "listening on 127.0.0.1:";
    if (!stage_->started() || !stage_->WaitForOutput(marker, 30.0)) return 0;
    const std::string out = stage_->Output();
    return static_cast<std::uint16_t>(std::stoi(out.substr(out.find(marker) + marker.size())));
  }

  /// The HIL loop in this process against the stage on `port`.
  HilResult RunHil(std::uint16_t port, double stop_time, int max_missed) {
    UdpBoardOptions board_options;
    board_options.stage_port = port;
    board_options.reply_timeout = 0.8e-3;
    UdpBoard board(board_options);
    ScopedBoardAttachment attachment(board);
    const Diagram diagram = BuildDiagram(testing::HilDiagramJson(stop_time), testing::HilDiagramDir(), "hil.json");
    HilOptions options;
    options.max_missed_streak = max_missed;
    options.max_overrun_streak = 1000;  // a loaded test machine may fall behind; the runner tests cover overruns
    return RunHilLoop(diagram, board, options);
  }

  fs::path dir_;
  std::unique_ptr<ChildProcess> stage_;
};

TEST_F(VirtualStageTest, HilRunReproducesTheSimulatedRun) {
  // The simulated run of the same diagram (plant as a subsystem, CVODE-free rk4).
  const Diagram simulated = LoadDiagram(testing::HilDiagramDir() / "pd_rigid_body.json");
  Simulator sim(simulated);
  const SimulationResult expected = sim.Run();

  // The stage integrates in wall-clock time, as a real plant does: a loop that fell behind on any tick ran a
  // different experiment, and the comparison below says nothing about the HIL path. Seen under load: 14 overruns
  // of 1000 ticks and no missed sample gave a 75 % different RMS error; 28 overruns and 3 missed samples, 16 %.
  // So only a run without overruns and missed samples is compared; up to three attempts (a fresh stage each),
  // and a machine that keeps none in real time skips the comparison.
  HilResult r;
  bool real_time = false;
  for (int attempt = 0; attempt < 3 && !real_time; ++attempt) {
    const std::uint16_t port = StartStage();
    ASSERT_NE(port, 0) << stage_->Output();
    r = RunHil(port, simulated.experiment().stop_time, 200);
    ASSERT_TRUE(r.completed) << r.stop_reason << "\nstage:\n" << stage_->Output();
    real_time = r.statistics.overruns == 0 && r.statistics.missed_samples == 0;
  }
  ASSERT_EQ(r.log.time.size(), expected.log.time.size());

  const double rmse_sim = expected.metrics.at("tracking_rmse");
  const double rmse_hil = r.metrics.at("tracking_rmse");
  RecordProperty("tracking_rmse_sim_um", std::to_string(rmse_sim * 1e6));
  RecordProperty("tracking_rmse_hil_um", std::to_string(rmse_hil * 1e6));
  EXPECT_GT(rmse_sim, 10e-6);  // a non-trivial error to reproduce
  // The HIL log names what the I/O subsystem logs.
  EXPECT_TRUE(r.log.Has("plant/encoder.counts"));
  EXPECT_TRUE(r.log.Has("plant/amplifier.voltage"));
  EXPECT_EQ(r.statistics.ticks, 1000);
  if (!real_time) {
    GTEST_SKIP() << "this machine did not keep the 1 kHz deadline in three attempts (the last: "
                 << r.statistics.overruns << " of " << r.statistics.ticks << " ticks overran, "
                 << r.statistics.missed_samples << " samples missed): the HIL-vs-simulation comparison needs real time";
  }
  // RMS tracking error within 10 % (a run in real time agrees to < 1 %).
  EXPECT_NEAR(rmse_hil, rmse_sim, 0.10 * rmse_sim)
      << "missed samples: " << r.statistics.missed_samples << ", overruns: " << r.statistics.overruns;
  // Sample by sample, the typical (median) position difference is a few per cent of the RMS error.
  EXPECT_LT(testing::MedianAbsoluteDifference(r.log.Column("position"), expected.log.Column("position")),
            0.05 * rmse_sim);
}

TEST_F(VirtualStageTest, KilledStageTriggersTheSafeStop) {
  const std::uint16_t port = StartStage();
  ASSERT_NE(port, 0) << stage_->Output();
  std::thread killer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    stage_->Signal(SIGKILL);
  });
  const HilResult r = RunHil(port, 2.0, 20);
  killer.join();
  EXPECT_FALSE(r.completed);
  EXPECT_THAT(r.stop_reason, HasSubstr("watchdog"));
  EXPECT_THAT(r.stop_reason, HasSubstr("all outputs zeroed"));
  EXPECT_GE(r.statistics.max_missed_streak, 20);
  // Killed ≈ 0.3 s after the killer thread starts; the loop itself may start up to that late on a loaded machine
  // (seen: the stop at 0.183 s of loop time with `make test` beside other builds). What holds on any machine: the safe
  // stop follows the 20 missed samples (≥ 20 ms of loop time), well before the 2 s run would end.
  EXPECT_GE(r.stop_time, 0.020);
  EXPECT_LT(r.stop_time, 1.2);
}

TEST_F(VirtualStageTest, DroppedPacketsTriggerTheSafeStopAndTheStageWatchdog) {
  const std::uint16_t port = StartStage({"--drop-from", "1.0", "--watchdog-ms", "50"});
  ASSERT_NE(port, 0) << stage_->Output();
  const HilResult r = RunHil(port, 3.0, 20);
  EXPECT_FALSE(r.completed);
  EXPECT_THAT(r.stop_reason, HasSubstr("watchdog"));
  EXPECT_LT(r.stop_time, 2.0);
  EXPECT_TRUE(stage_->WaitForOutput("watchdog: no outputs for 50 ms, forces zeroed", 5.0)) << stage_->Output();
  EXPECT_THAT(stage_->Output(), HasSubstr("fault injection: dropping every packet"));
}

TEST_F(VirtualStageTest, HilCommandWritesTheRunFilesAndStatistics) {
  const std::uint16_t port = StartStage();
  ASSERT_NE(port, 0) << stage_->Output();
  ChildProcess hil({"hil", (testing::HilDiagramDir() / "pd_rigid_body.json").string(), "--board", "udp", "--port",
                    std::to_string(port), "--replace",
                    "plant=" + (testing::HilDiagramDir() / "subsystems" / "hil_io.json").string(), "--duration",
                    "0.5", "--max-missed", "200", "--max-overruns", "1000", "--out", (dir_ / "out").string()},
                   dir_ / "hil.log");
  ASSERT_EQ(hil.Wait(), 0) << hil.Output();
  EXPECT_THAT(hil.Output(), HasSubstr("500 ticks at 1000 Hz"));
  const auto summary = nlohmann::json::parse(ReadFile(dir_ / "out" / "summary.json"));
  EXPECT_EQ(summary["hil"]["completed"], true);
  EXPECT_EQ(summary["hil"]["loop"]["ticks"], 500);
  EXPECT_TRUE(summary["metrics"].contains("tracking_rmse"));
  const std::string signals = ReadFile(dir_ / "out" / "signals.csv");
  EXPECT_THAT(signals.substr(0, signals.find('\n')), HasSubstr("tracking_error"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "timing.csv"));

  // Without a stage the command fails fast and says what to start; the earlier run's files in its --out are gone
  // (issue 30: a run that does not finish leaves no earlier summary.json looking like its own).
  fs::create_directories(dir_ / "out2");
  for (const char* name : {"summary.json", "signals.csv", "timing.csv", "summary.json.tmp4242"}) {
    std::ofstream(dir_ / "out2" / name) << "an earlier run\n";
  }
  std::ofstream(dir_ / "out2" / "notes.txt") << "the user's\n";
  ChildProcess alone({"hil", (testing::HilDiagramDir() / "pd_rigid_body.json").string(), "--board", "udp", "--port",
                      "9", "--replace", "plant=" + (testing::HilDiagramDir() / "subsystems" / "hil_io.json").string(),
                      "--out", (dir_ / "out2").string()},
                     dir_ / "alone.log");
  EXPECT_EQ(alone.Wait(), 1);
  EXPECT_THAT(alone.Output(), HasSubstr("no virtual stage answers on 127.0.0.1:9"));
  for (const char* name : {"summary.json", "signals.csv", "timing.csv", "summary.json.tmp4242"}) {
    EXPECT_FALSE(fs::exists(dir_ / "out2" / name)) << name;
  }
  EXPECT_TRUE(fs::exists(dir_ / "out2" / "notes.txt"));
}

// An outputs packet as a client (or any local process) sends it: `volts` on analog channel 0.
BoardPacket OutputsPacket(std::uint32_t sequence, double volts) {
  BoardPacket packet;
  packet.type = PacketType::kOutputs;
  packet.sequence = sequence;
  packet.analog_volts[0] = volts;
  return packet;
}

// Issue 30: one outputs packet with NaN, inf, 1e308 V or beyond the channel's ±10 V ended the stage with a message
// blaming the solver step (exit 3). It is a fault: not applied, the forces zeroed, the stage stops, and the report
// names the packet, the channel and the value.
TEST_F(VirtualStageTest, ABadOutputsPacketIsAFaultNamingThePacketAndTheValue) {
  const fs::path io = testing::HilDiagramDir() / "subsystems" / "hil_io.json";
  const StageWiring wiring = StageWiring::FromIoFile(io);
  ASSERT_EQ(wiring.analog_outputs.size(), 1u);
  EXPECT_EQ(wiring.analog_outputs[0].limit, 10.0);  // the analog_output's limit in the I/O file
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<double, std::string>> cases = {
      {std::numeric_limits<double>::quiet_NaN(), "channel 0 carries nan V, not a finite voltage"},
      {inf, "channel 0 carries inf V, not a finite voltage"},
      {-inf, "channel 0 carries -inf V, not a finite voltage"},
      {1e308, "channel 0 carries 1e+308 V, beyond the channel's limit of ±10 V"},
      {-10.5, "channel 0 carries -10.5 V, beyond the channel's limit of ±10 V"}};
  for (const auto& [volts, says] : cases) {
    VirtualStageOptions options;
    options.duration = 5.0;  // a safety net: the fault must stop it long before
    VirtualStage stage(testing::HilDiagramDir() / "subsystems" / "plant.json", wiring, options);
    LoopbackUdpSocket client(0);
    ASSERT_TRUE(client.SendTo(stage.port(), OutputsPacket(6, 2.5)));  // applied
    ASSERT_TRUE(client.SendTo(stage.port(), OutputsPacket(7, volts)));
    ASSERT_TRUE(client.SendTo(stage.port(), OutputsPacket(8, 1.0)));  // never read: the stage stopped at 7
    std::atomic<bool> stop{false};
    std::ostringstream events;
    const VirtualStageReport report = stage.Run(stop, events);
    EXPECT_THAT(report.fault, HasSubstr("outputs packet 7 (t = ")) << volts;
    EXPECT_THAT(report.fault, HasSubstr(says));
    EXPECT_THAT(report.fault, HasSubstr("every force is zeroed and the stage stopped"));
    EXPECT_THAT(report.fault, Not(HasSubstr("step")));
    EXPECT_EQ(report.outputs, 1) << "only packet 6 is applied";
    EXPECT_LT(report.time, 2.0) << "stopped by the fault, not by the duration";
    EXPECT_EQ(stage.forces(), std::vector<double>{0.0});
    EXPECT_THAT(events.str(), HasSubstr("fault: outputs packet 7"));
  }
  // Within ±limit nothing is a fault: the stage runs its duration.
  VirtualStageOptions options;
  options.duration = 0.2;
  VirtualStage stage(testing::HilDiagramDir() / "subsystems" / "plant.json", wiring, options);
  LoopbackUdpSocket client(0);
  ASSERT_TRUE(client.SendTo(stage.port(), OutputsPacket(1, -10.0)));
  std::atomic<bool> stop{false};
  std::ostringstream events;
  const VirtualStageReport report = stage.Run(stop, events);
  EXPECT_EQ(report.fault, "");
  EXPECT_EQ(report.outputs, 1);
}

// The stage's loop applies an outputs packet without allocating (it held each force as a new one-point input series:
// two vectors per packet): a run that applies 200 packets allocates what a run without packets does.
TEST_F(VirtualStageTest, OutputsPacketsAreAppliedWithoutAllocating) {
  const StageWiring wiring = StageWiring::FromIoFile(testing::HilDiagramDir() / "subsystems" / "hil_io.json");
  VirtualStageOptions options;
  options.duration = 0.1;
  options.watchdog_timeout = 10.0;  // no watchdog event (its line is text)
  const auto allocations_in_run = [&](int packets) {
    VirtualStage stage(testing::HilDiagramDir() / "subsystems" / "plant.json", wiring, options);
    LoopbackUdpSocket client(0);
    for (int k = 0; k < packets; ++k) client.SendTo(stage.port(), OutputsPacket(static_cast<std::uint32_t>(k), 0.01 * k));
    std::atomic<bool> stop{false};
    std::ostringstream events;
    const long before = testing::AllocationCount();
    const VirtualStageReport report = stage.Run(stop, events);
    const long allocations = testing::AllocationCount() - before;
    EXPECT_EQ(report.outputs, packets);
    EXPECT_EQ(stage.forces(), std::vector<double>{packets > 0 ? 0.01 * (packets - 1) : 0.0});
    return allocations;
  };
  const long without = allocations_in_run(0);
  const long with = allocations_in_run(200);
  EXPECT_LE(with, without) << "200 outputs packets cost " << with - without << " allocations";
}

TEST_F(VirtualStageTest, TheStageCommandStopsOnABadPacketWithExitOneAndThePacket) {
  const std::uint16_t port = StartStage();
  ASSERT_NE(port, 0) << stage_->Output();
  LoopbackUdpSocket client(0);
  ASSERT_TRUE(client.SendTo(port, OutputsPacket(3, std::numeric_limits<double>::quiet_NaN())));
  EXPECT_EQ(stage_->WaitFor(20.0), 1) << stage_->Output();
  EXPECT_THAT(stage_->Output(), HasSubstr("virtual-stage: outputs packet 3 (t = "));
  EXPECT_THAT(stage_->Output(), HasSubstr("analog output channel 0 carries nan V"));
  EXPECT_THAT(stage_->Output(), Not(HasSubstr("solver")));
}

// Issue 30: `virtual-stage --duration -1` or `nan` and `hil --duration -1` ran until killed; `--period-ms 1e-9` was
// accepted. Every such value is refused while the options are parsed: exit 2, naming the option.
TEST_F(VirtualStageTest, DurationsAndPeriodsOutsideTheirRangeAreRefusedAtParseTime) {
  const std::string plant = (testing::HilDiagramDir() / "subsystems" / "plant.json").string();
  const std::string io = (testing::HilDiagramDir() / "subsystems" / "hil_io.json").string();
  const std::vector<std::pair<std::string, std::string>> stage_options = {
      {"--duration", "-1"},       {"--duration", "nan"},   {"--duration", "inf"},   {"--duration", "0"},
      {"--duration", "1e9"},      {"--period-ms", "1e-9"}, {"--period-ms", "nan"},  {"--period-ms", "5000"},
      {"--watchdog-ms", "0"},     {"--watchdog-ms", "inf"}, {"--drop-from", "nan"}};
  for (const auto& [option, value] : stage_options) {
    ChildProcess stage({"virtual-stage", plant, "--io", io, "--port", "0", option, value}, dir_ / "refused.log");
    EXPECT_EQ(stage.WaitFor(20.0), 2) << option << " " << value << ": " << stage.Output();
    EXPECT_THAT(stage.Output(), HasSubstr(option)) << value;
    EXPECT_THAT(stage.Output(), HasSubstr(value + " is not a number in ")) << option;
    EXPECT_THAT(stage.Output(), Not(HasSubstr("listening"))) << option << " " << value;
  }
  const std::vector<std::pair<std::string, std::string>> hil_options = {
      {"--duration", "-1"}, {"--duration", "nan"}, {"--duration", "1e12"}, {"--reply-timeout-ms", "nan"}};
  for (const auto& [option, value] : hil_options) {
    ChildProcess hil({"hil", (testing::HilDiagramDir() / "pd_rigid_body.json").string(), "--board", "udp", "--port",
                      "9", "--replace", "plant=" + io, option, value, "--out", (dir_ / "out").string()},
                     dir_ / "hil.log");
    EXPECT_EQ(hil.WaitFor(20.0), 2) << option << " " << value << ": " << hil.Output();
    EXPECT_THAT(hil.Output(), HasSubstr(value + " is not a number in ")) << option;
  }
}

}  // namespace
}  // namespace mb
