// Sweeps within bounds (issue 30): a random sample is drawn run by run, not held (RandomSweepSampler), with the values
// the sweep file always gave; a resumed sweep runs again a row recorded "ok" whose metric is NaN; a shard manifest
// whose counts exceed the ceiling (kMaxSweepRunsCeiling) is refused naming the file and the key.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/csv.h"
#include "tests/alloc_counter.h"
#include "tests/tools/batch/sweep_test_files.h"
#include "tools/batch/shard.h"
#include "tools/batch/sweep.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using ::testing::HasSubstr;

// Three uniform keys: per draw one engine() call each, in the keys' (alphabetical) order.
json RandomSweep(std::size_t samples) {
  json sweep = json::parse(R"({"random": {"seed": 11, "parameters": {
      "k.a": {"uniform": [1, 2]}, "k.b": {"uniform": [-5, 5]}, "k.c": {"uniform": [0, 1]}}}})");
  sweep["random"]["samples"] = samples;
  return sweep;
}

// Draw `index` as the sweep file's documentation defines it (tools/batch/sweep_spec.h): std::mt19937_64(seed), per draw
// the keys in order, each low + (high − low)·(engine() >> 11)·2⁻⁵³; computed here from scratch.
std::vector<double> DocumentedDraw(std::size_t index) {
  std::mt19937_64 engine(11);
  engine.discard(3 * index);
  const double lows[] = {1, -5, 0}, highs[] = {2, 5, 1};
  std::vector<double> values;
  for (int k = 0; k < 3; ++k) {
    values.push_back(lows[k] + (highs[k] - lows[k]) * (static_cast<double>(engine() >> 11) * 0x1.0p-53));
  }
  return values;
}

std::vector<double> Values(const SweepRun& run) {
  std::vector<double> values;
  for (const auto& [key, value] : run.assignments) values.push_back(value.get<double>());
  return values;
}

TEST(RandomSweepTest, AMillionDrawsAreNotHeldWhenTheSweepIsParsed) {
  // Issue 30: 10⁷ samples held every draw (4.3 GB). Now parsing allocates the same few blocks for any sample size.
  const long before_small = testing::AllocationCount();
  const SweepSpec small = ParseSweep(RandomSweep(10), "s.json");
  const long small_allocations = testing::AllocationCount() - before_small;
  const long before = testing::AllocationCount();
  const SweepSpec spec = ParseSweep(RandomSweep(1000000), "s.json", 1000000);
  const long allocations = testing::AllocationCount() - before;
  EXPECT_EQ(spec.run_count(), 1000000u);
  EXPECT_EQ(small.run_count(), 10u);
  EXPECT_LE(allocations, small_allocations + 10) << "parsing 10⁶ samples allocated " << allocations
                                                 << " times, 10 samples " << small_allocations;
  // What is checked before any run is each distribution's bounds, not every draw.
  EXPECT_EQ(spec.AllAssignments().size(), 6u);
}

TEST(RandomSweepTest, DrawsAreTheDocumentedValuesInAnyOrder) {
  const SweepSpec spec = ParseSweep(RandomSweep(200000), "s.json", 200000);
  // Jumps back and forth, across checkpoints (every kRandomCheckpointEvery draws), and the same run twice.
  for (const std::size_t i : {std::size_t{0}, std::size_t{199999}, std::size_t{1}, kRandomCheckpointEvery - 1,
                              kRandomCheckpointEvery, kRandomCheckpointEvery, std::size_t{123456}, std::size_t{2},
                              std::size_t{123457}}) {
    EXPECT_EQ(Values(spec.run(i)), DocumentedDraw(i)) << "run " << i;
    EXPECT_EQ(spec.run(i).id, fmt::format("{:04d}", i));
  }
  EXPECT_THROW(spec.run(200000), std::out_of_range);
  // A copy (RunSweepShard takes the spec by value) shares the sampler and draws the same.
  SweepSpec copy = spec;
  copy.KeepRuns({5, 70000});
  EXPECT_EQ(Values(copy.run(1)), DocumentedDraw(70000));
  EXPECT_EQ(copy.run(1).id, "70000");
}

TEST(RandomSweepTest, ParallelStreamsOfRunsDrawTheSameAsOneAfterAnother) {
  const std::size_t n = 40000;
  const SweepSpec spec = ParseSweep(RandomSweep(n), "s.json");
  std::vector<std::vector<double>> sequential(n), parallel(n);
  for (std::size_t i = 0; i < n; ++i) sequential[i] = Values(spec.run(i));
  const SweepSpec fresh = ParseSweep(RandomSweep(n), "s.json");
  std::vector<std::thread> workers;
  for (std::size_t w = 0; w < 4; ++w) {  // each its own ascending block, as tbb::parallel_for hands them out
    workers.emplace_back([&, w] {
      for (std::size_t i = w * n / 4; i < (w + 1) * n / 4; ++i) parallel[i] = Values(fresh.run(i));
    });
  }
  for (auto& t : workers) t.join();
  EXPECT_EQ(parallel, sequential);
  EXPECT_EQ(sequential[n - 1], DocumentedDraw(n - 1));
}

class SweepBoundsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_sweep_bounds_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    diagram_ = dir_ / "gain.json";
    std::ofstream(diagram_) << testing::GainDiagram().dump(2);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::vector<std::string> Lines(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
  static void WriteLines(const fs::path& path, const std::vector<std::string>& lines) {
    std::ofstream out(path);
    for (const auto& line : lines) out << line << "\n";
  }

  fs::path dir_;
  fs::path diagram_;
};

TEST_F(SweepBoundsTest, AResumedSweepRunsAgainAnOkRowWhoseMetricIsNotFinite) {
  const SweepSpec spec = ParseSweep(json::parse(R"({"list": [{"k.gain": 1}, {"k.gain": 2}, {"k.gain": 3},
      {"k.gain": 4}]})"), "s.json");
  SweepOptions options;
  options.progress = false;
  const fs::path out = dir_ / "out";
  ASSERT_EQ(RunSweep(diagram_, spec, out, options).ran, 4);
  // Rows 0001 and 0002 say "ok" with a NaN and an infinite y_final; row 0003's metric cell is not a number.
  auto lines = Lines(out / "runs.csv");
  ASSERT_EQ(lines.size(), 5u);
  ASSERT_EQ(lines[0], "id,status,k.gain,y_final,c_final,wall_time_s,error");
  const auto with_metric = [](const std::string& line, const std::string& value) {
    std::vector<std::string> cells = SplitCsvLine(line);
    cells[3] = value;
    return CsvLine(cells);
  };
  lines[2] = with_metric(lines[2], "nan");
  lines[3] = with_metric(lines[3], "-inf");
  lines[4] = with_metric(lines[4], "8x");
  WriteLines(out / "runs.csv", lines);

  std::vector<std::size_t> run_again;
  std::mutex run_again_mutex;  // on_result is called on the workers' threads (SweepOptions::on_result)
  options.on_result = [&](std::size_t i, const SimulationResult&) {
    const std::lock_guard<std::mutex> lock(run_again_mutex);
    run_again.push_back(i);
  };
  const SweepOutcome again = RunSweep(diagram_, spec, out, options);
  EXPECT_EQ(again.resumed, 1);
  EXPECT_EQ(again.ran, 3);
  std::sort(run_again.begin(), run_again.end());
  EXPECT_EQ(run_again, (std::vector<std::size_t>{1, 2, 3}));
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(again.rows[i].metrics.at("y_final"), 2.0 * static_cast<double>(i + 1)) << i;
  }
  EXPECT_EQ(SplitCsvLine(Lines(out / "runs.csv")[2])[3], "4");
}

TEST_F(SweepBoundsTest, AManifestCountAboveTheCeilingIsRefusedNamingTheFileAndTheKey) {
  const SweepSpec spec = ParseSweep(json::parse(R"({"grid": {"k.gain": [1, 2, 3, 4]}})"), "s.json");
  SweepOptions options;
  options.progress = false;
  const fs::path a = dir_ / "a", b = dir_ / "b";
  RunSweepShard(diagram_, spec, SweepShard{0, 2}, a, options);
  RunSweepShard(diagram_, spec, SweepShard{1, 2}, b, options);
  ASSERT_EQ(MergeSweepShards({a, b}, dir_ / "merged").runs, 4u);

  const fs::path manifest = b / kShardManifest;
  std::ifstream in(manifest);
  const json original = json::parse(in);
  const auto refused = [&](const std::string& key, const json& value, const std::string& expected) {
    json edited = original;
    edited[key] = value;
    std::ofstream(manifest) << edited.dump(2);
    try {
      MergeSweepShards({a, b}, dir_ / "merged2");
      ADD_FAILURE() << key << " = " << value.dump() << ": merged";
    } catch (const std::invalid_argument& e) {
      EXPECT_THAT(e.what(), HasSubstr(manifest.string() + ": \"" + key + "\": " + expected)) << e.what();
      EXPECT_THAT(e.what(), HasSubstr("delete the folder and run the shard again"));
    }
    EXPECT_FALSE(fs::exists(dir_ / "merged2" / "runs.csv"));
    // Resuming the shard reads the same manifest: refused too.
    EXPECT_THROW(RunSweepShard(diagram_, spec, SweepShard{1, 2}, b, options), std::invalid_argument) << key;
  };
  refused("runs", json::parse("1e12"), "1000000000000.0 is not a run count from 1 to 10000000");
  refused("runs", json(std::uint64_t{1000000000000}), "1000000000000 is not a run count from 1 to 10000000");
  refused("runs", json(kMaxSweepRunsCeiling + 1), "10000001 is not a run count from 1 to 10000000");
  refused("shards", json(std::uint64_t{1} << 40), "1099511627776 is not a shard count from 1 to \"runs\" (4)");
  refused("shard", json(7), "7 is not a shard index from 0 to \"shards\" - 1 (1)");
}

}  // namespace
}  // namespace mb
