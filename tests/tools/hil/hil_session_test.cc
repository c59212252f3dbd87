// The HIL session as a library call (tools/hil/hil_session.h) against the in-process test board: the defaults
// `motionblocks hil` documents, the prepared diagram, summary.json's keys and values, the three files written and an
// earlier run's removed, a safe stop requested by the stop flag. The real no-hardware path (the `hil` command against
// `motionblocks virtual-stage`) is tests/hw/virtual_stage_test.cc.

#include <algorithm>
#include <atomic>
#include <fstream>
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/hw/hil_test_util.h"
#include "tests/hw/test_board.h"
#include "tools/hil/hil_session.h"
#include "tools/report/output_files.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using nlohmann::json;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Settings for the shipped HIL diagram, its plant swapped for the I/O subsystem, writing into `out`.
HilSessionSettings ShippedHilSettings(const fs::path& out) {
  HilSessionSettings settings;
  settings.diagram = (testing::HilDiagramDir() / "pd_rigid_body.json").string();
  settings.replacements = {"plant=" + (testing::HilDiagramDir() / "subsystems" / "hil_io.json").string()};
  settings.out = out;
  return settings;
}

fs::path EmptyFolder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The keys of an object, sorted (as nlohmann::json holds them).
std::vector<std::string> Keys(const json& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items()) keys.push_back(item.key());
  return keys;
}

TEST(HilSessionTest, SettingsHoldTheCommandLineDefaults) {
  const HilSessionSettings s;
  EXPECT_EQ(s.duration, 0.0);
  EXPECT_EQ(s.out, fs::path("out/hil"));
  EXPECT_EQ(s.board, HilBoardKind::kUdp);
  EXPECT_EQ(s.udp.stage_port, 0);
  EXPECT_EQ(s.udp.reply_timeout, 0.5e-3);
  EXPECT_EQ(s.quanser.board_type, "q8_usb");
  EXPECT_EQ(s.quanser.board_identifier, "0");
  EXPECT_EQ(s.quanser.encoder_channels, 1);
  EXPECT_EQ(s.quanser.analog_outputs, 1);
  EXPECT_EQ(s.quanser.watchdog_timeout, 0.01);
  EXPECT_EQ(s.loop.max_missed_streak, 20);
  EXPECT_EQ(s.loop.max_overrun_streak, 10);
  EXPECT_EQ(s.loop.realtime.fifo_priority, 0);
  EXPECT_FALSE(s.loop.realtime.lock_memory);
  EXPECT_THAT(HilSessionOutputNames(), ElementsAre("signals.csv", "timing.csv", "summary.json"));
  EXPECT_EQ(ParseHilBoardKind("udp"), HilBoardKind::kUdp);
  EXPECT_EQ(ParseHilBoardKind("quanser"), HilBoardKind::kQuanser);
  EXPECT_THROW(ParseHilBoardKind("q8"), std::invalid_argument);
}

TEST(HilSessionTest, PrepareSwapsThePlantAppliesOverridesAndTheDuration) {
  HilSessionSettings settings = ShippedHilSettings(EmptyFolder("mb_hil_session_prepare") / "out");
  settings.overrides = {"controller.kp=123"};
  settings.duration = 0.25;
  const PreparedHilDiagram prepared = PrepareHilDiagram(settings);
  EXPECT_EQ(prepared.json["defaultExperiment"]["stopTime"], 0.25);
  bool swapped = false;
  for (const auto& element : prepared.json["elements"]) {
    if (element["name"] == "plant") {
      swapped = element["diagram"].get<std::string>().find("hil_io.json") != std::string::npos;
    }
    if (element["name"] == "controller") {
      EXPECT_EQ(element["parameters"]["kp"], 123);
    }
  }
  EXPECT_TRUE(swapped) << prepared.json.dump(2);

  settings.replacements.clear();
  try {
    PrepareHilDiagram(settings);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("hil: give --replace plant=HIL_IO.json"));
  }
}

TEST(HilSessionTest, PrepareRefusesAnOutputFolderHoldingTheDiagram) {
  const fs::path dir = EmptyFolder("mb_hil_session_refuse");
  fs::copy_file(testing::HilDiagramDir() / "pd_rigid_body.json", dir / "summary.json");
  HilSessionSettings settings = ShippedHilSettings(dir);
  settings.diagram = (dir / "summary.json").string();
  EXPECT_THROW(PrepareHilDiagram(settings), OutputReplacesInputError);
}

TEST(HilSessionTest, RunOnABoardWritesTheThreeFilesAndTheSummary) {
  const fs::path out = EmptyFolder("mb_hil_session_run") / "out";
  fs::create_directories(out);
  for (const char* name : {"summary.json", "timing.csv", "signals.csv.tmp4242"}) {
    std::ofstream(out / name) << "an earlier run\n";
  }
  std::ofstream(out / "notes.txt") << "the user's\n";
  HilSessionSettings settings = ShippedHilSettings(out);
  settings.overrides = {"controller.kp=400"};
  settings.duration = 0.2;
  const PreparedHilDiagram prepared = PrepareHilDiagram(settings);
  testing::TestBoard board;
  std::atomic<bool> stop{false};
  HilSessionStart start;
  int starts = 0;
  const HilSessionResult result = RunHilSessionOnBoard(settings, prepared.json, board, &stop,
                                                       [&](const HilSessionStart& s) {
                                                         start = s;
                                                         ++starts;
                                                         // The earlier run's files are still there: removed next.
                                                         EXPECT_TRUE(fs::exists(out / "summary.json"));
                                                       });
  EXPECT_EQ(starts, 1);
  EXPECT_EQ(start.name, "hil_pd_rigid_body");
  EXPECT_EQ(start.board, "test board");
  EXPECT_NEAR(start.duration, 0.2, 1e-12);
  EXPECT_NEAR(start.period, 1e-3, 1e-15);

  ASSERT_TRUE(result.run.completed) << result.run.stop_reason;
  EXPECT_EQ(result.run.statistics.ticks, 200);
  const json summary = result.ToJson();
  EXPECT_THAT(Keys(summary), ElementsAre("diagram", "hil", "metric_units", "metrics", "name", "overrides",
                                         "replacements", "samples"));
  EXPECT_EQ(summary["diagram"], fs::absolute(settings.diagram).string());
  EXPECT_EQ(summary["name"], "hil_pd_rigid_body");
  EXPECT_EQ(summary["overrides"], json::array({"controller.kp=400"}));
  EXPECT_EQ(summary["replacements"].get<std::vector<std::string>>(), settings.replacements);
  EXPECT_EQ(summary["metric_units"], json({{"tracking_max", "m"}, {"tracking_rmse", "m"}}));
  EXPECT_THAT(Keys(summary["metrics"]), ElementsAre("tracking_max", "tracking_rmse"));
  EXPECT_EQ(summary["samples"], 201);
  EXPECT_THAT(Keys(summary["hil"]), ElementsAre("board", "completed", "loop", "realtime", "stop_reason",
                                                "stop_time_s"));
  EXPECT_EQ(summary["hil"]["board"], "test board");
  EXPECT_EQ(summary["hil"]["completed"], true);
  EXPECT_EQ(summary["hil"]["stop_reason"], "");
  EXPECT_NEAR(summary["hil"]["stop_time_s"].get<double>(), 0.2, 1e-12);
  const json& loop = summary["hil"]["loop"];
  EXPECT_THAT(Keys(loop), ElementsAre("compute_s", "latency_s", "max_missed_streak", "max_overrun_streak",
                                      "missed_samples", "overruns", "period_jitter_s", "period_s", "ticks"));
  EXPECT_EQ(loop["ticks"], 200);
  EXPECT_EQ(loop["period_s"], 1e-3);
  EXPECT_THAT(Keys(loop["latency_s"]), ElementsAre("max", "mean", "p50", "p99", "p99.9"));
  EXPECT_THAT(Keys(loop["period_jitter_s"]), ElementsAre("max_abs", "rms"));
  EXPECT_THAT(Keys(loop["compute_s"]), ElementsAre("max", "mean", "p99"));

  // The files: summary.json is ToJson, signals.csv the log as `run` writes it, timing.csv one row per tick; the
  // earlier run's files are gone, the user's stay.
  EXPECT_EQ(json::parse(ReadFile(out / "summary.json")), summary);
  const std::string signals = ReadFile(out / "signals.csv");
  EXPECT_THAT(signals.substr(0, signals.find('\n')), HasSubstr("tracking_error"));
  const std::string timing = ReadFile(out / "timing.csv");
  EXPECT_EQ(timing.substr(0, timing.find('\n')), "time_s,latency_s,compute_s,flags");
  EXPECT_EQ(std::count(timing.begin(), timing.end(), '\n'), 201);
  EXPECT_FALSE(fs::exists(out / "signals.csv.tmp4242"));
  EXPECT_TRUE(fs::exists(out / "notes.txt"));
}

TEST(HilSessionTest, TheStopFlagSafeStopsTheLoopAndTheFilesSayWhy) {
  const fs::path out = EmptyFolder("mb_hil_session_stop") / "out";
  HilSessionSettings settings = ShippedHilSettings(out);
  settings.duration = 0.5;
  testing::TestBoard board;
  std::atomic<bool> stop{true};  // requested before the first tick
  const HilSessionResult result = RunHilSessionOnBoard(settings, PrepareHilDiagram(settings).json, board, &stop);
  EXPECT_FALSE(result.run.completed);
  EXPECT_THAT(result.run.stop_reason, HasSubstr("stop requested (SIGINT/SIGTERM)"));
  EXPECT_EQ(board.safe_stops(), 1);
  const json summary = json::parse(ReadFile(out / "summary.json"));
  EXPECT_EQ(summary["hil"]["completed"], false);
  EXPECT_EQ(summary["hil"]["stop_reason"], result.run.stop_reason);
}

}  // namespace
}  // namespace mb
