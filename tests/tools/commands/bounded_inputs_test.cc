// Reads and requests with a bound (issue 30): every input a command reads is a regular file within the input size
// limit (a device or a FIFO is refused without being opened, so nothing blocks or fills memory), and counts a user
// gives (--max-steps, fit-gpr --restarts and --period) are refused outside their documented range. Each case runs
// the executable as users call it; exit 2 (bad input) and the exact message.
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::CommandResult;
using testing::RunMotionblocksIn;

constexpr const char* kDevice =
    ": the {} is a character device, not a regular file; give the path of a regular file (save a stream or a pipe's "
    "output to a file first)";

std::string DeviceMessage(const std::string& path, const std::string& kind) {
  std::string text = kDevice;
  text.replace(text.find("{}"), 2, kind);
  return "motionblocks: error: " + path + text + "\n";
}

class BoundedInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mb_bounded_inputs_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    std::ostringstream csv;  // a small GP training table (cogging, τ = 22.5 mm)
    csv << "x_m,v_m_s,dob_N\n";
    for (double v : {0.05, 0.1}) {
      for (int i = 0; i < 60; ++i) {
        const double x = 0.002 * i;
        csv << x << ',' << v << ',' << 2.0 * std::sin(2.0 * M_PI * x / 0.0225) + 0.5 * v + 0.02 * std::sin(7.3 * i)
            << '\n';
      }
    }
    std::ofstream(dir_ / "table.csv") << csv.str();
    ASSERT_EQ(::mkfifo((dir_ / "pipe").c_str(), 0600), 0);
  }
  void TearDown() override { fs::remove_all(dir_); }
  CommandResult Run(const std::vector<std::string>& arguments) { return RunMotionblocksIn(dir_, arguments); }
  static std::string Diagram() { return std::string(MB_SOURCE_DIR) + "/diagrams/paper/conventional.json"; }
  fs::path dir_;
};

TEST_F(BoundedInputs, DevicesAreRefusedAsEveryInput) {
  CommandResult r = Run({"run", "/dev/zero"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, DeviceMessage("/dev/zero", "diagram file"));
  r = Run({"compare", Diagram(), "--measurement", "/dev/urandom", "--out", "o"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, DeviceMessage("/dev/urandom", "measurement log"));
  r = Run({"run", Diagram(), "--input", "u=/dev/zero", "--out", "o"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, DeviceMessage("/dev/zero", "measurement log"));
  r = Run({"fit-gpr", "/dev/zero", "--disturbance-column", "d", "-o", "m.json"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, DeviceMessage("/dev/zero", "table"));
  r = Run({"predict-gpr", "/dev/zero", "table.csv", "-o", "p.csv"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, DeviceMessage("/dev/zero", "GP model file"));
  r = Run({"stability", Diagram(), "--gpr", "/dev/urandom"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, DeviceMessage("/dev/urandom", "GP model file"));
}

// A FIFO without a writer would block an open forever: it is refused from its status (the test would hang).
TEST_F(BoundedInputs, AFifoIsRefusedWithoutBlocking) {
  CommandResult r = Run({"run", "pipe"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, "motionblocks: error: pipe: the diagram file is a FIFO (named pipe), not a regular file; give "
                      "the path of a regular file (save a stream or a pipe's output to a file first)\n");
  r = Run({"stability", Diagram(), "--gpr", "pipe"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("pipe: the GP model file is a FIFO (named pipe), not a regular file"));
  r = Run({"fit-gpr", "pipe", "--disturbance-column", "d", "-o", "m.json"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("pipe: the table is a FIFO (named pipe), not a regular file"));
}

TEST_F(BoundedInputs, AFileAboveTheSizeLimitIsRefusedNamingTheFlag) {
  const CommandResult r = Run({"--max-input-mb", "0.001", "run", Diagram(), "--out", "o"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, "motionblocks: error: " + Diagram() + ": the diagram file is " +
                          std::to_string(fs::file_size(Diagram())) + " bytes (" +
                          [] {
                            std::ostringstream s;
                            s << static_cast<double>(fs::file_size(Diagram())) / 1e6;
                            return s.str();
                          }() +
                          " MB), more than the input limit of 0.001 MB (1000 bytes); if it is meant to be this "
                          "large, raise the limit with --max-input-mb (e.g. --max-input-mb 2)\n");
  EXPECT_EQ(Run({"--max-input-mb", "nan", "run", Diagram(), "--out", "o"}).exit_code, 2);
}

TEST_F(BoundedInputs, MaxStepsNanOrInfinityIsRefused) {
  for (const char* n : {"nan", "inf"}) {
    const CommandResult r = Run({"run", Diagram(), "--max-steps", n, "--out", "o"});
    EXPECT_EQ(r.exit_code, 2) << n;
    EXPECT_EQ(r.output, std::string("motionblocks: error: --max-steps ") + n +
                            ": the step limit must be a finite number in [1, 1e+13] (default 1e+08); give the number "
                            "of steps a run may take\n");
  }
}

TEST_F(BoundedInputs, FitGprRestartsAndPeriodHaveARange) {
  const std::vector<std::string> fit = {"fit-gpr", "table.csv", "--position-column", "x_m", "--velocity-column",
                                        "v_m_s", "--disturbance-column", "dob_N", "-o", "m.json"};
  std::vector<std::string> args = fit;
  args.insert(args.end(), {"--restarts", "100000000"});
  CommandResult r = Run(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, "motionblocks: error: 100000000 restarts is outside the valid range [0, 1000] (each start runs "
                      "up to 400 evaluations of the posterior); give fewer (fit-gpr --restarts; 2 to 10 is usual)\n");
  args = fit;
  args.insert(args.end(), {"--period", "1e-300"});
  r = Run(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output, "motionblocks: error: the period 1e-300 m is outside the valid range [1e-06, 1e+06] m; give the "
                      "spatial period of the disturbance in metres (e.g. the pole pitch, 0.0225 for 22.5 mm: fit-gpr "
                      "--period)\n");
  // A seed beyond 64 bits was read as 2^64 − 1 without a word (tests/hostile).
  args = fit;
  args.insert(args.end(), {"--seed", "123456789012345678901234567890"});
  r = Run(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("give a whole number from 0 to 999999999999999999"));
  EXPECT_FALSE(fs::exists(dir_ / "m.json"));
}

// A run logging more signals than --max-plots draws that many figures and names the rest in report.html.
TEST_F(BoundedInputs, TheReportDrawsAtMostMaxPlotsSignals) {
  std::string elements, log;
  for (int i = 0; i < 5; ++i) {
    elements += (i ? "," : "") + std::string(R"({"name": "c)") + std::to_string(i) +
                R"(", "type": "constant", "parameters": {"value": 1}})";
    log += (i ? "," : "") + std::string(R"("c)") + std::to_string(i) + R"(.y")";
  }
  std::ofstream(dir_ / "d.json") << R"({"schemaVersion": "1.0", "name": "many",
      "defaultExperiment": {"startTime": 0, "stopTime": 0.01}, "solver": {"type": "rk4", "step": 0.001},
      "elements": [)" << elements << R"(], "log": [)" << log << "]}";
  CommandResult r = Run({"run", "d.json", "--max-plots", "2", "--out", "o"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "o" / "signal_1.png"));
  EXPECT_FALSE(fs::exists(dir_ / "o" / "signal_2.png"));
  std::ifstream in(dir_ / "o" / "report.html");
  const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(page, HasSubstr("3 more figures not drawn: a report draws at most 2 (raise it with motionblocks "
                              "--max-plots N). Their data is in the command's files. Not drawn: c2.y, c3.y, c4.y."));
  r = Run({"run", "d.json", "--max-plots", "0", "--out", "o"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--max-plots: give a figure count from 1 to 100000"));
}

// A "notes" of the wrong type is refused as soon as the file is read: a million small objects in it (nlohmann's
// callback parser scanned the enclosing array at every object's end: 400,000 took 58 s, a million would take
// minutes) parse in linear time before the type check.
TEST_F(BoundedInputs, AHugeNotesArrayIsRefusedQuickly) {
  {
    std::ofstream out(dir_ / "notes.json");
    out << R"({"schemaVersion": "1.0", "name": "n", "elements": [], "notes": [)";
    for (int i = 0; i < 1000000; ++i) out << (i ? "," : "") << R"({"x":1})";
    out << "]}";
  }
  const auto start = std::chrono::steady_clock::now();
  const CommandResult r = Run({"run", "notes.json", "--out", "o"});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("/notes: must be string, got an array"));
  EXPECT_LT(seconds, 120.0) << "linear: about 2 s in Release, well under a minute under ASan";
}

}  // namespace
}  // namespace mb
