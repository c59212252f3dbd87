// Results complete or marked incomplete (issue 30, item 7), as users meet them: an interrupted `run` leaves none of
// an earlier run's files beside its own; a killed `improve` leaves improve.json saying "complete": false, a finished
// one "complete": true with its stop; an earlier run's improve.json is gone while the new run works; `sweep
// --max-runs` has a ceiling, and a sweep above the default limit says what its rows will take before it starts. Each case kills or runs the executable and reads what is left.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::CommandResult;
using testing::RunMotionblocksIn;

const std::string kEmps = std::string(MB_SOURCE_DIR) + "/diagrams/emps";
const std::string kPaper = std::string(MB_SOURCE_DIR) + "/diagrams/paper";

// `motionblocks ARGUMENTS` in the background (no shell), output to `log`; killed when destroyed.
class Background {
 public:
  Background(const std::vector<std::string>& arguments, const fs::path& log) {
    std::vector<std::string> argv = {MB_MOTIONBLOCKS_EXE};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawn(&pid_, args[0], &actions, nullptr, args.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Background() { Kill(); }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  bool started() const { return pid_ > 0; }
  bool Running() {
    int status = 0;
    if (pid_ > 0 && waitpid(pid_, &status, WNOHANG) == pid_) pid_ = -1;
    return pid_ > 0;
  }
  void Kill() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

class CompleteResults : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_complete_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "out");
  }
  void TearDown() override { fs::remove_all(dir_); }
  void Write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }
  // Polls every 2 ms until `done` or `timeout_s`; returns whether `done` held.
  template <class Done>
  static bool PollUntil(Done done, double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
  }
  static bool HasTemporaryFile(const fs::path& folder, const std::string& stem) {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(folder, error)) {
      if (entry.path().filename().string().starts_with(stem + ".tmp")) return true;
    }
    return false;
  }
  fs::path dir_;
};

// Issue 30: an interrupted `run` left the earlier run's summary.json beside a signals.csv.tmp<pid>.
TEST_F(CompleteResults, AnInterruptedRunLeavesNoEarlierResultBesideItsOwn) {
  const fs::path out = dir_ / "out";
  fs::create_directories(out / "plot");
  for (const char* name : {"summary.json", "report.html", "signals.csv", "signal_7.png", "diagram.svg",
                           "plot/signal_7.gp", "plot/signal_7.dat", "plot/gnuplot.log", "plot/diagram.dot"}) {
    Write(out / name, "from an earlier run\n");
  }
  Write(out / "signals.csv.tmp99999", "a run killed earlier\n");
  Write(out / "notes.txt", "the user's own file\n");
  Write(out / "plot" / "notes.txt", "the user's own file\n");
  // The paper's conventional loop, 2000 s of it (about a minute): long enough to be killed while its log streams.
  Background run({"run", kPaper + "/conventional.json", "--set", "defaultExperiment.stopTime=2000", "--out",
                  out.string()},
                 dir_ / "run.log");
  ASSERT_TRUE(run.started());
  const bool streaming = PollUntil(
      [&] {
        return (!fs::exists(out / "signals.csv.tmp99999") && HasTemporaryFile(out, "signals.csv")) || !run.Running();
      },
      60.0) && run.Running();
  run.Kill();
  std::ifstream log(dir_ / "run.log");
  ASSERT_TRUE(streaming) << std::string(std::istreambuf_iterator<char>(log), std::istreambuf_iterator<char>());
  for (const char* name : {"summary.json", "report.html", "signals.csv", "signal_7.png", "diagram.svg",
                           "plot/signal_7.gp", "plot/signal_7.dat", "plot/gnuplot.log", "plot/diagram.dot"}) {
    EXPECT_FALSE(fs::exists(out / name)) << name << " of the earlier run is still there";
  }
  EXPECT_TRUE(fs::exists(out / "notes.txt"));  // only the run's own file names are removed
  EXPECT_TRUE(fs::exists(out / "plot" / "notes.txt"));
}

// On the EMPS record's first 8 s (what is written when does not need the whole record; a step still takes seconds).
TEST_F(CompleteResults, AKilledImproveSaysIncompleteAndAFinishedOneComplete) {
  const fs::path out = dir_ / "out";
  const std::string log = (dir_ / "first_8s.csv").string();
  {
    std::ifstream in(kEmps + "/data/DATA_EMPS.csv");
    std::ofstream f(log);
    std::string line;
    for (int i = 0; i < 8001 && std::getline(in, line); ++i) f << line << "\n";
  }
  Write(out / "improve.json", R"({"complete": true, "stop": "max_effects", "steps": [], "earlier": true})");
  Background improve({"improve", kEmps + "/rigid_body.json", "--measurement", log,
                      "--max-effects", "3", "--out", out.string()},
                     dir_ / "improve.log");
  ASSERT_TRUE(improve.started());
  // The earlier run's improve.json goes before the first step's is written (step 0, the refit, takes a while).
  EXPECT_TRUE(PollUntil([&] { return !fs::exists(out / "improve.json"); }, 60.0))
      << "the earlier run's improve.json stayed while this run worked";
  ASSERT_TRUE(PollUntil([&] { return fs::exists(out / "improve.json") || !improve.Running(); }, 120.0));
  improve.Kill();  // as a user's Ctrl-\, an OOM kill or a lost machine would
  const auto killed = testing::ReadJsonFile(out / "improve.json");  // whole: written by rename
  EXPECT_EQ(killed["complete"], false) << killed.dump(1).substr(0, 2000);
  EXPECT_FALSE(killed.contains("earlier"));
  EXPECT_GE(killed["steps"].size(), 1u);

  // Run to the end (step 0 only): complete, with the stop and its reason, which are set after the last step.
  const CommandResult done = RunMotionblocksIn(
      dir_, {"improve", kEmps + "/rigid_body.json", "--measurement", log, "--max-effects", "0", "--out",
             out.string()});
  ASSERT_EQ(done.exit_code, 0) << done.output;
  const auto finished = testing::ReadJsonFile(out / "improve.json");
  EXPECT_EQ(finished["complete"], true);
  EXPECT_EQ(finished["stop"], "max_effects");
  EXPECT_EQ(finished["stop_reason"], "stopped after --max-effects 0 effect(s)");
  // The keys the progress files have, and the same ones.
  for (const char* key : {"diagram", "measurement", "validation", "mode", "max_effects", "min_relative_gain", "steps",
                          "accepted", "stop", "residual_not_white"}) {
    EXPECT_TRUE(finished.contains(key)) << key;
  }
}

TEST_F(CompleteResults, SweepMaxRunsHasACeiling) {
  Write(dir_ / "gain.json", R"({"schemaVersion": "1.0", "name": "gain",
    "defaultExperiment": {"startTime": 0, "stopTime": 0.01, "stepSize": 0.001}, "solver": {"type": "rk4", "step": 0.001},
    "elements": [{"name": "c", "type": "constant", "parameters": {"value": 2.0}}]})");
  Write(dir_ / "s.json", R"({"list": [{"c.value": 1}]})");
  for (const char* value : {"1e12", "10000001", "0", "nan"}) {
    const CommandResult r =
        RunMotionblocksIn(dir_, {"sweep", "gain.json", "s.json", "--out", "o", "--max-runs", value});
    EXPECT_EQ(r.exit_code, 2) << value << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr("--max-runs")) << value;
  }
  const CommandResult ok = RunMotionblocksIn(dir_, {"sweep", "gain.json", "s.json", "--out", "o", "--max-runs", "10000000"});
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  // Above the default limit the command says what the rows will take before anything runs (here nothing does: the
  // element is unknown).
  Write(dir_ / "big.json", R"({"random": {"seed": 1, "samples": 200001, "parameters": {"d.value": {"uniform": [0, 1]}}}})");
  const CommandResult big =
      RunMotionblocksIn(dir_, {"sweep", "gain.json", "big.json", "--out", "o2", "--max-runs", "300000"});
  EXPECT_EQ(big.exit_code, 2) << big.output;
  EXPECT_THAT(big.output, HasSubstr("sweep: 200001 runs; every row is kept until runs.csv and runs.json are written at "
                                    "the end: about 0.5 GB of memory"));
}

}  // namespace
}  // namespace mb
