// tools/batch/sweep.h: grid, list and seeded random sweeps (order, repeatability, errors), parallel runs with one row
// of metrics each, resuming from runs.csv, and the shipped sweeps in diagrams/paper/sweeps.

#include "tools/batch/sweep.h"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/csv.h"
#include "engine/diagram_loader.h"
#include "tests/tools/batch/sweep_test_files.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

using mb::testing::GainDiagram;

class SweepRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_sweep_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    diagram_ = dir_ / "gain.json";
    std::ofstream(diagram_) << GainDiagram().dump(2);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::vector<std::string> Lines(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }

  fs::path dir_;
  fs::path diagram_;
};

TEST(ParseSweepTest, GridIsCartesianProductLastKeyFastest) {
  const SweepSpec spec = ParseSweep(json::parse(R"({"grid": {"a.x": [1, 2], "b.y": [10, 20, 30]}})"), "s.json");
  EXPECT_EQ(spec.kind, "grid");
  ASSERT_EQ(spec.run_count(), 6u);
  EXPECT_EQ(spec.parameters, (std::vector<std::string>{"a.x", "b.y"}));
  EXPECT_EQ(spec.run(0).id, "0000");
  EXPECT_EQ(spec.run(5).id, "0005");
  EXPECT_EQ(spec.run(1).assignments[0].second, 1);
  EXPECT_EQ(spec.run(1).assignments[1].second, 20);
  EXPECT_EQ(spec.run(3).assignments[0].second, 2);
  EXPECT_EQ(spec.run(3).assignments[1].second, 10);
}

// Runs are generated from their index: a billion-point grid allowed by the caller holds its 3000 axis values, not a
// billion runs (materialised, it would need > 100 GB), and any run is there at once, in sweep order.
TEST(ParseSweepTest, AHugeGridIsGeneratedIndexByIndex) {
  json axis = json::array();
  for (int v = 0; v < 1000; ++v) axis.push_back(v);
  const json sweep = {{"grid", {{"a.x", axis}, {"b.y", axis}, {"c.z", axis}}}};
  const SweepSpec spec = ParseSweep(sweep, "s.json", 2'000'000'000);
  EXPECT_EQ(spec.run_count(), 1'000'000'000u);
  EXPECT_EQ(spec.AllAssignments().size(), 3000u);
  const SweepRun r = spec.run(123'456'789);
  EXPECT_EQ(r.id, "123456789");
  ASSERT_EQ(r.assignments.size(), 3u);
  EXPECT_EQ(r.assignments[0].second, 123);  // the last key varies fastest
  EXPECT_EQ(r.assignments[1].second, 456);
  EXPECT_EQ(r.assignments[2].second, 789);
  EXPECT_EQ(spec.PositionOf("123456789"), 123'456'789u);
  EXPECT_EQ(spec.PositionOf("0123456789"), std::nullopt);  // not an id this sweep writes
  EXPECT_THROW(spec.run(1'000'000'000), std::out_of_range);
}

TEST(ParseSweepTest, KeptRunsKeepTheirIds) {
  SweepSpec spec = ParseSweep(json::parse(R"({"list": [{"a.x": 1}, {"a.x": 2}, {"a.x": 3}, {"a.x": 4}]})"), "s.json");
  spec.KeepRuns({0, 2});
  ASSERT_EQ(spec.run_count(), 2u);
  EXPECT_EQ(spec.run(1).id, "0002");
  EXPECT_EQ(spec.run(1).assignments[0].second, 3);
  EXPECT_EQ(spec.PositionOf("0002"), 1u);
  EXPECT_EQ(spec.PositionOf("0001"), std::nullopt);
  EXPECT_THROW(spec.KeepRuns({1, 0}), std::invalid_argument);
}

TEST(ParseSweepTest, ListKeepsEntriesAndMissingKeys) {
  const SweepSpec spec = ParseSweep(
      json::parse(R"({"list": [{"a.x": [0.05]}, {"a.x": [0.1], "defaultExperiment.stopTime": 8}]})"), "s.json");
  ASSERT_EQ(spec.run_count(), 2u);
  EXPECT_EQ(spec.parameters, (std::vector<std::string>{"a.x", "defaultExperiment.stopTime"}));
  ASSERT_EQ(spec.run(0).assignments.size(), 1u);
  EXPECT_EQ(spec.run(0).assignments[0].second, json::parse("[0.05]"));
  ASSERT_EQ(spec.run(1).assignments.size(), 2u);
  EXPECT_EQ(spec.run(1).assignments[1].second, 8);
}

TEST(ParseSweepTest, RandomIsRepeatableAndWithinBounds) {
  const json sweep = json::parse(R"({"random": {"seed": 7, "samples": 50, "parameters": {
      "a.u": {"uniform": [1, 2]}, "a.l": {"log_uniform": [10, 1000]}, "a.i": {"integer": [2, 4]},
      "a.c": {"choice": ["x", "y"]}}}})");
  const SweepSpec first = ParseSweep(sweep, "s.json");
  const SweepSpec second = ParseSweep(sweep, "s.json");
  ASSERT_EQ(first.run_count(), 50u);
  std::set<long long> integers;
  std::set<std::string> choices;
  for (std::size_t r = 0; r < first.run_count(); ++r) {
    EXPECT_EQ(first.run(r).assignments, second.run(r).assignments) << r;
    for (const auto& [key, value] : first.run(r).assignments) {
      if (key == "a.u") {
        EXPECT_GE(value.get<double>(), 1.0);
        EXPECT_LT(value.get<double>(), 2.0);
      } else if (key == "a.l") {
        EXPECT_GE(value.get<double>(), 10.0);
        EXPECT_LT(value.get<double>(), 1000.0);
      } else if (key == "a.i") {
        integers.insert(value.get<long long>());
      } else {
        choices.insert(value.get<std::string>());
      }
    }
  }
  EXPECT_EQ(integers, (std::set<long long>{2, 3, 4}));
  EXPECT_EQ(choices, (std::set<std::string>{"x", "y"}));
  json other = sweep;
  other["random"]["seed"] = 8;
  EXPECT_NE(ParseSweep(other, "s.json").run(0).assignments, first.run(0).assignments);
}

TEST(ParseSweepTest, ErrorsNameWhereAndHowToFix) {
  auto message = [](const char* text) {
    try {
      ParseSweep(json::parse(text), "s.json");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_EQ(message(R"({"grid": {"a.x": [1]}, "list": [{"a.x": 1}]})"),
            "s.json: give exactly one of \"grid\", \"list\" or \"random\" (found 2)");
  EXPECT_EQ(message(R"({"grid": {"a.x": []}})"), "s.json: /grid/a.x: give a non-empty array of values");
  EXPECT_EQ(message(R"({"grid": {"ax": [1]}})"),
            "s.json: /grid: 'ax': write a swept key as element.parameter (e.g. plant.payload_mass) or "
            "defaultExperiment.stopTime");
  EXPECT_EQ(message(R"({"random": {"seed": 1, "samples": 3, "parameters": {"a.x": {"uniform": [2, 1]}}}})"),
            "s.json: /random/parameters/a.x/uniform: bounds must satisfy low < high, got [2, 1]");
  EXPECT_EQ(message(R"({"random": {"seed": 1, "samples": 3, "parameters": {"a.x": {"normal": [0, 1]}}}})"),
            "s.json: /random/parameters/a.x: unknown distribution 'normal' (uniform, log_uniform, integer, choice)");
  // An integer range beyond 2^53 drew INT64_MIN (tests/hostile).
  EXPECT_EQ(message(R"({"random": {"seed": 1, "samples": 3, "parameters": {"a.x": {"integer": [0, 1e300]}}}})"),
            "s.json: /random/parameters/a.x/integer: bounds must lie within ±2^53 (±9007199254740992), exact as "
            "numbers in JSON, got [0, 1e+300]");
}

TEST(SplitCsvLineTest, QuotedCells) {
  EXPECT_EQ(SplitCsvLine("a,\"[1,2]\",\"say \"\"hi\"\"\","),
            (std::vector<std::string>{"a", "[1,2]", "say \"hi\"", ""}));
}

TEST_F(SweepRunTest, ParallelRunsGiveOneRowOfMetricsEach) {
  const SweepSpec spec = ParseSweep(json::parse(R"({"set": {"c.value": 3.0},
      "grid": {"k.gain": [1, 2, 3, 4, 5, 6, 7]}})"), "s.json");
  SweepOptions options;
  options.jobs = 3;
  options.progress = false;
  std::vector<double> from_callback(spec.run_count(), 0.0);
  options.on_result = [&](std::size_t i, const SimulationResult& r) { from_callback[i] = r.metrics.at("y_final"); };
  const SweepOutcome outcome = RunSweep(diagram_, spec, dir_ / "out", options);
  EXPECT_EQ(outcome.ran, 7);
  EXPECT_EQ(outcome.failed, 0);
  ASSERT_EQ(outcome.rows.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(outcome.rows[i].status, "ok");
    EXPECT_DOUBLE_EQ(outcome.rows[i].metrics.at("y_final"), 3.0 * static_cast<double>(i + 1));
    EXPECT_DOUBLE_EQ(outcome.rows[i].metrics.at("c_final"), 3.0);
    EXPECT_DOUBLE_EQ(from_callback[i], 3.0 * static_cast<double>(i + 1));
  }
  const auto lines = Lines(dir_ / "out" / "runs.csv");
  ASSERT_EQ(lines.size(), 8u);
  EXPECT_EQ(lines[0], "id,status,k.gain,y_final,c_final,wall_time_s,error");
  EXPECT_EQ(SplitCsvLine(lines[3])[0], "0002");
  EXPECT_EQ(SplitCsvLine(lines[3])[2], "3");
  EXPECT_DOUBLE_EQ(std::stod(SplitCsvLine(lines[3])[3]), 9.0);
  std::ifstream in(dir_ / "out" / "runs.json");
  const json j = json::parse(in);
  ASSERT_EQ(j["runs"].size(), 7u);
  EXPECT_EQ(j["runs"][6]["parameters"]["k.gain"], 7);
  EXPECT_DOUBLE_EQ(j["runs"][6]["metrics"]["y_final"].get<double>(), 21.0);
  EXPECT_EQ(j["metric_units"]["y_final"], "1");
  EXPECT_EQ(j["set"]["c.value"], 3.0);
}

TEST_F(SweepRunTest, ResumesOnlyMissingAndFailedRuns) {
  const SweepSpec spec = ParseSweep(json::parse(R"({"list": [{"k.gain": 1}, {"k.gain": 2}, {"k.gain": 3}]})"),
                                    "s.json");
  SweepOptions options;
  options.progress = false;
  const fs::path out = dir_ / "out";
  EXPECT_EQ(RunSweep(diagram_, spec, out, options).ran, 3);

  // Everything done: nothing runs, the rows come back from runs.csv.
  SweepOutcome again = RunSweep(diagram_, spec, out, options);
  EXPECT_EQ(again.ran, 0);
  EXPECT_EQ(again.resumed, 3);
  EXPECT_DOUBLE_EQ(again.rows[2].metrics.at("y_final"), 6.0);

  // Drop run 0001 (as if interrupted) and mark 0002 failed: exactly those two run again.
  auto lines = Lines(out / "runs.csv");
  ASSERT_EQ(lines.size(), 4u);
  {
    std::ofstream rewrite(out / "runs.csv");
    rewrite << lines[0] << "\n" << lines[1] << "\n";
    auto cells = SplitCsvLine(lines[3]);
    rewrite << "0002,failed," << cells[2] << ",,,0.0,boom\n";
  }
  std::atomic<int> called = 0;  // on_result is called on the workers' threads (SweepOptions::on_result)
  options.on_result = [&](std::size_t, const SimulationResult&) { ++called; };
  again = RunSweep(diagram_, spec, out, options);
  EXPECT_EQ(again.ran, 2);
  EXPECT_EQ(again.resumed, 1);
  EXPECT_EQ(called.load(), 2);
  EXPECT_DOUBLE_EQ(again.rows[1].metrics.at("y_final"), 4.0);
  EXPECT_EQ(Lines(out / "runs.csv").size(), 4u);  // rewritten: one row per run

  // Another sweep into the same folder is refused.
  const SweepSpec other = ParseSweep(json::parse(R"({"list": [{"k.gain": 5}, {"k.gain": 2}, {"k.gain": 3}]})"),
                                     "s.json");
  try {
    RunSweep(diagram_, other, out, options);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              (out / "runs.csv").string() +
                  ":2: run 0000 has k.gain = 1 there, but this sweep gives 5: written by another sweep; use another "
                  "--out or delete it");
  }
  // --fresh runs everything again.
  options.resume = false;
  EXPECT_EQ(RunSweep(diagram_, other, out, options).ran, 3);
}

TEST_F(SweepRunTest, ExperimentKeysAndFailedRuns) {
  // stopTime from the sweep; a negative step size is rejected by the loader: that run fails, the others go on.
  const SweepSpec spec = ParseSweep(json::parse(R"({"list": [{"defaultExperiment.stopTime": 0.02},
      {"defaultExperiment.stopTime": -1}]})"), "s.json");
  SweepOptions options;
  options.progress = false;
  std::vector<double> last_time(2, 0.0);
  options.on_result = [&](std::size_t i, const SimulationResult& r) { last_time[i] = r.log.time.back(); };
  const SweepOutcome outcome = RunSweep(diagram_, spec, dir_ / "out", options);
  EXPECT_EQ(outcome.rows[0].status, "ok");
  EXPECT_NEAR(last_time[0], 0.02, 1e-12);
  EXPECT_EQ(outcome.rows[1].status, "failed");
  EXPECT_FALSE(outcome.rows[1].error.empty());
  EXPECT_EQ(outcome.failed, 1);
}

TEST_F(SweepRunTest, UnknownElementIsRefusedBeforeAnyRun) {
  const SweepSpec spec = ParseSweep(json::parse(R"({"grid": {"kk.gain": [1, 2]}})"), "s.json");
  SweepOptions options;
  options.progress = false;
  EXPECT_THROW(RunSweep(diagram_, spec, dir_ / "out", options), DiagramError);
  EXPECT_FALSE(fs::exists(dir_ / "out" / "runs.csv"));
}

TEST(ShippedSweepsTest, EverySweepParsesAndAppliesToItsDiagram) {
  const fs::path folder = fs::path(MB_SOURCE_DIR) / "diagrams" / "paper" / "sweeps";
  int count = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const SweepSpec spec = ReadSweepFile(entry.path());
    std::ifstream in(entry.path());
    const json raw = json::parse(in);
    ASSERT_TRUE(raw.contains("diagram")) << "a shipped sweep names its diagram (relative to the sweep)";
    const fs::path diagram = entry.path().parent_path() / raw["diagram"].get<std::string>();
    json base = ReadDiagramJson(diagram);
    for (std::size_t i = 0; i < spec.run_count(); ++i) {
      const SweepRun run = spec.run(i);
      json j = ApplySweepAssignments(ApplySweepAssignments(base, spec.fixed, diagram.string()), run.assignments,
                                     diagram.string());
      EXPECT_NO_THROW(BuildDiagram(j, diagram.parent_path(), diagram.string())) << run.id;
    }
    ++count;
  }
  EXPECT_GE(count, 2);
}

}  // namespace
}  // namespace mb
