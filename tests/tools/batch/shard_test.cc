// tools/batch/shard.h: --shard parsing (x/y from 1, --shard-index K/N from 0, the schedulers' variables), the
// partition (deterministic, disjoint, covering), shards resumed, and sweep-merge (equal to the single-process
// runs.csv; a missing run, a shard given twice, a shard of another sweep or shard count, a value edited after the
// run, a non-finite metric in an ok row and conflicting rows refused with the folder, the line and the fix).

#include "tools/batch/shard.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include <unistd.h>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/csv.h"
#include "engine/diagram_loader.h"
#include "tests/tools/batch/sweep_test_files.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// An environment of the given variables only.
EnvironmentLookup Environment(std::map<std::string, std::string> variables) {
  return [variables = std::move(variables)](const char* name) -> const char* {
    const auto it = variables.find(name);
    return it == variables.end() ? nullptr : it->second.c_str();
  };
}

std::string ShardError(const std::string& text, const std::map<std::string, std::string>& variables = {}) {
  try {
    const SweepShard s = ParseSweepShard(text, Environment(variables));
    return "no error: " + std::to_string(s.index) + "/" + std::to_string(s.count);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
}

std::string ShardIndexError(const std::string& text) {
  try {
    const SweepShard s = ParseSweepShardIndex(text);
    return "no error: " + std::to_string(s.index) + "/" + std::to_string(s.count);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
}

TEST(ParseSweepShardTest, XOfYCountsFromOne) {
  // The two halves, as Jest and Playwright write them (issue 28: `--shard 2/2` used to fail).
  EXPECT_EQ(ShardError("1/2"), "no error: 0/2");
  EXPECT_EQ(ShardError("2/2"), "no error: 1/2");
  const SweepShard s = ParseSweepShard("3/5", Environment({}));
  EXPECT_EQ(s.index, 2u);
  EXPECT_EQ(s.count, 5u);
  EXPECT_EQ(ParseSweepShard("1/1", Environment({})).count, 1u);
  EXPECT_EQ(ShardLabel(s), "3/5");
}

TEST(ParseSweepShardTest, ShardIndexCountsFromZero) {
  EXPECT_EQ(ShardIndexError("0/2"), "no error: 0/2");
  EXPECT_EQ(ShardIndexError("1/2"), "no error: 1/2");
  EXPECT_EQ(ShardLabel(ParseSweepShardIndex("1/2")), "2/2");  // the same shard as --shard 2/2
  EXPECT_EQ(ShardIndexError("2/2"),
            "--shard-index 2/2: --shard-index counts from 0, so K runs from 0 to 1 (write --shard-index 0/2 … 1/2); "
            "--shard x/y counts from 1 (1 <= x <= y)");
  EXPECT_EQ(ShardIndexError("0/0"), "--shard-index 0/0: the number of shards must be at least 1");
  const std::string usage = "': write K/N, shard index K of N counted from 0 (0 <= K < N, e.g. 0/4 to 3/4); --shard "
                            "x/y counts from 1";
  EXPECT_EQ(ShardIndexError("auto"), "--shard-index 'auto" + usage);
  EXPECT_EQ(ShardIndexError("1"), "--shard-index '1" + usage);
  EXPECT_EQ(ShardIndexError("-1/2"), "--shard-index '-1/2" + usage);
}

TEST(ParseSweepShardTest, MalformedShardsSayHowToWriteThemAndWhichNumbering) {
  const std::string usage =
      "': write x/y, shard x of y counted from 1 (1 <= x <= y, e.g. 1/4 to 4/4, as Jest and Playwright count), or "
      "auto or auto/N (index from the scheduler, counted from 0); --shard-index K/N counts from 0 (0 <= K < N)";
  EXPECT_EQ(ShardError("3"), "--shard '3" + usage);
  EXPECT_EQ(ShardError("a/4"), "--shard 'a/4" + usage);
  EXPECT_EQ(ShardError("-1/4"), "--shard '-1/4" + usage);
  EXPECT_EQ(ShardError("1/x"), "--shard '1/x" + usage);
  EXPECT_EQ(ShardError("1/4/2"), "--shard '1/4/2" + usage);
  EXPECT_EQ(ShardError(""), "--shard '" + usage);
  EXPECT_EQ(ShardError("5/4"),
            "--shard 5/4: --shard x/y counts from 1, so x runs from 1 to 4 (write --shard 1/4 … 4/4); --shard-index "
            "K/N counts from 0 (0 <= K < N)");
  EXPECT_EQ(ShardError("0/2"),
            "--shard 0/2: --shard x/y counts from 1, so x runs from 1 to 2 (write --shard 1/2 … 2/2); --shard-index "
            "K/N counts from 0 (0 <= K < N)");
  EXPECT_EQ(ShardError("0/0"), "--shard 0/0: the number of shards must be at least 1");
}

TEST(ParseSweepShardTest, AutoTakesTheSchedulersVariables) {
  const auto slurm = ParseSweepShard("auto", Environment({{"SLURM_ARRAY_TASK_ID", "3"},
                                                          {"SLURM_ARRAY_TASK_COUNT", "8"}}));
  EXPECT_EQ(slurm.index, 3u);
  EXPECT_EQ(slurm.count, 8u);
  const auto k8s = ParseSweepShard("auto/4", Environment({{"JOB_COMPLETION_INDEX", "1"}}));
  EXPECT_EQ(k8s.index, 1u);
  EXPECT_EQ(k8s.count, 4u);
  const auto mpi = ParseSweepShard("auto", Environment({{"OMPI_COMM_WORLD_RANK", "2"},
                                                        {"OMPI_COMM_WORLD_SIZE", "3"}}));
  EXPECT_EQ(mpi.index, 2u);
  EXPECT_EQ(mpi.count, 3u);
  // Slurm first, then Kubernetes, then Open MPI.
  EXPECT_EQ(ParseSweepShard("auto/9", Environment({{"JOB_COMPLETION_INDEX", "5"}, {"OMPI_COMM_WORLD_RANK", "0"},
                                                   {"OMPI_COMM_WORLD_SIZE", "1"}}))
                .index,
            5u);
  // A Slurm array without the count variable takes N from auto/N.
  EXPECT_EQ(ParseSweepShard("auto/6", Environment({{"SLURM_ARRAY_TASK_ID", "5"}})).count, 6u);
}

TEST(ParseSweepShardTest, AutoErrorsNameTheVariable) {
  EXPECT_EQ(ShardError("auto"),
            "--shard auto: none of SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX, OMPI_COMM_WORLD_RANK is set: run it as "
            "a Slurm array task, a Kubernetes indexed Job or under mpirun, or give the shard as x/y (counted from 1)");
  EXPECT_EQ(ShardError("auto", {{"JOB_COMPLETION_INDEX", "2"}}),
            "--shard auto: JOB_COMPLETION_INDEX=2 gives K but nothing gives N: write --shard auto/N (N = the number "
            "of shards)");
  EXPECT_EQ(ShardError("auto", {{"SLURM_ARRAY_TASK_ID", "4"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}),
            "--shard auto: SLURM_ARRAY_TASK_ID=4 but there are 4 shards (numbered 0 to 3): submit the array as "
            "--array=0-3");
  EXPECT_EQ(ShardError("auto/2", {{"JOB_COMPLETION_INDEX", "2"}}),
            "--shard auto: JOB_COMPLETION_INDEX=2 but there are 2 shards (numbered 0 to 1): write --shard auto/N "
            "with N = the Job's completions");
  EXPECT_EQ(ShardError("auto", {{"SLURM_ARRAY_TASK_ID", "x1"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}),
            "--shard auto: SLURM_ARRAY_TASK_ID='x1' is not a whole number >= 0");
  EXPECT_EQ(ShardError("auto/3", {{"OMPI_COMM_WORLD_RANK", "1"}, {"OMPI_COMM_WORLD_SIZE", "4"}}),
            "--shard auto/3: OMPI_COMM_WORLD_SIZE=4 says 4 shards: give --shard auto or auto/4");
  EXPECT_EQ(ShardError("auto/0", {{"JOB_COMPLETION_INDEX", "0"}}),
            "--shard auto/0: the number of shards must be at least 1");
}

TEST(ShardPositionsTest, DisjointCoveringAndRoundRobin) {
  for (std::size_t runs : {1u, 2u, 7u, 100u, 101u}) {
    for (std::size_t n = 1; n <= 7; ++n) {
      std::multiset<std::size_t> all;
      for (std::size_t k = 0; k < n; ++k) {
        const auto positions = ShardPositions(runs, {k, n});
        EXPECT_EQ(positions, ShardPositions(runs, {k, n}));  // the same every time
        for (const std::size_t p : positions) {
          EXPECT_EQ(p % n, k);
          all.insert(p);
        }
      }
      ASSERT_EQ(all.size(), runs) << runs << " runs, " << n << " shards";  // disjoint and covering
      for (std::size_t i = 0; i < runs; ++i) EXPECT_EQ(all.count(i), 1u);
    }
  }
  EXPECT_EQ(ShardPositions(10, {1, 4}), (std::vector<std::size_t>{1, 5, 9}));
}

TEST(SweepFingerprintTest, SameFilesSameFingerprint) {
  const json random = json::parse(R"({"random": {"seed": 7, "samples": 5,
      "parameters": {"k.gain": {"uniform": [0, 1]}}}})");
  const json diagram = testing::GainDiagram();
  const std::string a = SweepFingerprint(ParseSweep(random, "s.json"), diagram);
  EXPECT_EQ(a, SweepFingerprint(ParseSweep(random, "other.json"), json::parse(diagram.dump(2))));
  EXPECT_EQ(a.rfind("fnv1a64:", 0), 0u);
  EXPECT_EQ(a.size(), 8u + 16u);
  json other_seed = random;
  other_seed["random"]["seed"] = 8;
  EXPECT_NE(a, SweepFingerprint(ParseSweep(other_seed, "s.json"), diagram));
  json other_diagram = diagram;
  other_diagram["elements"][0]["parameters"]["value"] = 2.5;
  EXPECT_NE(a, SweepFingerprint(ParseSweep(random, "s.json"), other_diagram));
}

// The folder's files as a shard that wrote them so would leave them: runs.csv rewritten to `rows` (header kept)
// and the manifest's content hash updated (a sweep that wrote such rows itself, not an edit after the run).
void RewriteShard(const fs::path& dir, const std::vector<std::vector<std::string>>& rows,
                  const json& manifest_changes = json::object()) {
  const CsvTextTable table = ReadCsvTextTable((dir / "runs.csv").string());
  {
    std::ofstream rewrite(dir / "runs.csv");
    rewrite << CsvLine(table.header) << "\n";
    for (const auto& row : rows) rewrite << CsvLine(row) << "\n";
  }
  std::ifstream in(dir / kShardManifest);
  json manifest = json::parse(in);
  manifest.update(manifest_changes);
  manifest[kShardContentKey] = ShardContentHash(manifest, dir);
  std::ofstream(dir / kShardManifest) << manifest.dump(2);
}

std::vector<std::vector<std::string>> ShardRowsOf(const fs::path& dir) {
  return ReadCsvTextTable((dir / "runs.csv").string()).rows;
}

class ShardRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_shard_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    diagram_ = dir_ / "gain.json";
    std::ofstream(diagram_) << testing::GainDiagram().dump(2);
    options_.progress = false;
    options_.jobs = 2;
    // These tests compare runs; each shard's report.html (gnuplot per figure) tripled their time. The merged sweep's
    // report is still written and tested (tests/tools/report/sweep_report_test.cc).
    options_.report = false;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs the shards K of N given into dir_/shard_K.
  std::vector<fs::path> RunShards(const SweepSpec& spec, std::size_t n, const std::vector<std::size_t>& ks) {
    std::vector<fs::path> dirs;
    for (const std::size_t k : ks) {
      dirs.push_back(dir_ / ("shard_" + std::to_string(k)));
      RunSweepShard(diagram_, spec, {k, n}, dirs.back(), options_);
    }
    return dirs;
  }

  std::string MergeError(const std::vector<fs::path>& dirs) {
    try {
      MergeSweepShards(dirs, dir_ / "merged");
      return "no error";
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
  }

  SweepSpec Grid() const {
    return ParseSweep(json::parse(R"({"set": {"c.value": 3.0},
        "grid": {"k.gain": [1, 2, 3, 4, 5, 6, 7], "defaultExperiment.stopTime": [0.01, 0.02]}})"), "s.json");
  }

  fs::path dir_;
  fs::path diagram_;
  SweepOptions options_;
};

TEST_F(ShardRunTest, MergedShardsEqualTheSingleProcessSweep) {
  for (const char* text : {R"({"grid": {"k.gain": [1, 2, 3, 4, 5, 6, 7], "defaultExperiment.stopTime": [0.01, 0.02]},
                                "set": {"c.value": 3.0}})",
                           R"({"list": [{"k.gain": 1}, {"c.value": 4}, {"k.gain": 3, "c.value": 5},
                                        {"defaultExperiment.stopTime": -1}]})",
                           R"({"random": {"seed": 11, "samples": 9, "parameters": {"k.gain": {"uniform": [0, 2]}}}})"}) {
    const SweepSpec spec = ParseSweep(json::parse(text), "s.json");
    fs::remove_all(dir_ / "whole");
    RunSweep(diagram_, spec, dir_ / "whole", options_);
    for (std::size_t n : {1u, 3u, 4u}) {
      std::vector<std::size_t> ks;
      for (std::size_t k = n; k-- > 0;) ks.push_back(k);  // any order
      for (const auto& d : fs::directory_iterator(dir_)) {
        if (d.path().filename().string().rfind("shard_", 0) == 0) fs::remove_all(d.path());
      }
      fs::remove_all(dir_ / "merged");
      const SweepMergeOutcome merged = MergeSweepShards(RunShards(spec, n, ks), dir_ / "merged");
      EXPECT_EQ(merged.runs, spec.run_count());
      EXPECT_EQ(testing::RunsWithoutWallTime(dir_ / "merged" / "runs.csv"),
                testing::RunsWithoutWallTime(dir_ / "whole" / "runs.csv"))
          << text << " in " << n << " shards";
      std::ifstream in(dir_ / "merged" / "runs.json");
      const json j = json::parse(in);
      ASSERT_EQ(j["runs"].size(), spec.run_count());
      EXPECT_EQ(j["runs"].back()["id"], spec.run(spec.run_count() - 1).id);
    }
  }
}

TEST_F(ShardRunTest, ShardsKeepGlobalIdsAndMergeTheirLogs) {
  options_.save_logs = true;
  const auto dirs = RunShards(Grid(), 3, {0, 1, 2});
  const CsvTextTable shard1 = ReadCsvTextTable((dirs[1] / "runs.csv").string());
  ASSERT_EQ(shard1.rows.size(), 5u);  // runs 1, 4, 7, 10, 13 of 14
  EXPECT_EQ(shard1.rows[0][0], "0001");
  EXPECT_EQ(shard1.rows[4][0], "0013");
  EXPECT_TRUE(fs::exists(dirs[1] / "runs" / "0013" / "signals.csv"));
  std::ifstream in(dirs[1] / kShardManifest);
  const json manifest = json::parse(in);
  EXPECT_EQ(manifest["shard"], 1);
  EXPECT_EQ(manifest["shards"], 3);
  EXPECT_EQ(manifest["runs"], 14);
  const SweepMergeOutcome merged = MergeSweepShards(dirs, dir_ / "merged");
  EXPECT_EQ(merged.copied_run_folders, 14u);
  EXPECT_TRUE(fs::exists(dir_ / "merged" / "runs" / "0013" / "signals.csv"));
}

TEST_F(ShardRunTest, AShardResumesAndRefusesAnotherFolder) {
  const SweepSpec spec = Grid();
  const auto dirs = RunShards(spec, 3, {1});
  // Drop the last run as if the shard had been interrupted: only that run runs again.
  const fs::path csv = dirs[0] / "runs.csv";
  const CsvTextTable table = ReadCsvTextTable(csv.string());
  {
    std::ofstream rewrite(csv);
    rewrite << CsvLine(table.header) << "\n";
    for (std::size_t r = 0; r + 1 < table.rows.size(); ++r) rewrite << CsvLine(table.rows[r]) << "\n";
  }
  const SweepOutcome again = RunSweepShard(diagram_, spec, {1, 3}, dirs[0], options_);
  EXPECT_EQ(again.ran, 1);
  EXPECT_EQ(again.resumed, 4);
  EXPECT_EQ(again.rows.back().id, "0013");

  auto error = [&](const SweepShard& shard, const SweepSpec& s, const fs::path& out) -> std::string {
    try {
      RunSweepShard(diagram_, s, shard, out, options_);
      return "no error";
    } catch (const std::exception& e) {
      return e.what();
    }
  };
  EXPECT_EQ(error({2, 3}, spec, dirs[0]),
            dirs[0].string() + ": holds shard 2/3 of this sweep, not 3/3: give --shard 2/3 to resume it, or use "
                               "another --out");
  const SweepSpec other = ParseSweep(json::parse(R"({"grid": {"k.gain": [1, 2, 3]}})"), "s.json");
  const std::string fingerprint = SweepFingerprint(spec, ReadDiagramJson(diagram_));
  const std::string other_fingerprint = SweepFingerprint(other, ReadDiagramJson(diagram_));
  EXPECT_EQ(error({1, 3}, other, dirs[0]),
            dirs[0].string() + ": holds shard 2/3 of another sweep (fingerprint " + fingerprint +
                ", this sweep and diagram give " + other_fingerprint +
                "): use another --out, or delete the folder to start over");
  RunSweep(diagram_, other, dir_ / "whole", options_);
  EXPECT_EQ(error({0, 2}, other, dir_ / "whole"),
            (dir_ / "whole").string() + ": holds a sweep run without --shard (runs.csv, no sweep-shard.json): use "
                                        "another --out for the shard");
  EXPECT_EQ(error({3, 4}, other, dir_ / "s34"),
            "--shard 4/4: the sweep has 3 runs, so this shard has none: use at most 3 shards");
}

TEST_F(ShardRunTest, MergeListsMissingRunsWithTheirShard) {
  const SweepSpec spec = Grid();
  const auto dirs = RunShards(spec, 4, {0, 2, 3});
  EXPECT_EQ(MergeError(dirs),
            "4 of 14 runs are missing: 0001 (shard 2/4), 0005 (shard 2/4), 0009 (shard 2/4), 0013 (shard 2/4): run "
            "their shard again with the same --out (it resumes) or add its folder, then merge again");
  EXPECT_FALSE(fs::exists(dir_ / "merged" / "runs.csv"));  // nothing written
  // A run cut short in a shard's runs.csv (an interrupted run) counts as missing.
  const auto all = RunShards(spec, 4, {1});
  const fs::path csv = all[0] / "runs.csv";
  const CsvTextTable table = ReadCsvTextTable(csv.string());
  {
    std::ofstream rewrite(csv);
    rewrite << CsvLine(table.header) << "\n" << CsvLine(table.rows[0]) << "\n0005,ok,2\n";
  }
  RewriteShard(all[0], {table.rows[0]});  // the shard's own hash over the row it finished
  EXPECT_EQ(MergeError({dirs[0], all[0], dirs[1], dirs[2]}),
            "3 of 14 runs are missing: 0005 (shard 2/4), 0009 (shard 2/4), 0013 (shard 2/4): run their shard again with the same --out "
            "(it resumes) or add its folder, then merge again");
}

// A folder given twice: its manifest's shard twice (before any run is counted twice).
TEST_F(ShardRunTest, MergeRefusesAShardGivenTwice) {
  const auto dirs = RunShards(Grid(), 2, {0, 1});
  const std::string manifest = (dirs[0] / kShardManifest).string();
  EXPECT_EQ(MergeError({dirs[0], dirs[1], dirs[0]}),
            manifest + " and " + manifest + " both say they hold shard 1/2: give each shard's folder once (a folder "
                                            "copied or run twice)");
}

TEST_F(ShardRunTest, MergeRefusesAShardOfAnotherSweep) {
  const auto dirs = RunShards(Grid(), 2, {0});
  const SweepSpec other = ParseSweep(json::parse(R"({"grid": {"k.gain": [1, 2, 3, 4, 5, 6, 7],
      "defaultExperiment.stopTime": [0.01, 0.03]}, "set": {"c.value": 3.0}})"), "s.json");
  RunSweepShard(diagram_, other, {1, 2}, dir_ / "other_1", options_);
  const std::string fa = SweepFingerprint(Grid(), ReadDiagramJson(diagram_));
  const std::string fb = SweepFingerprint(other, ReadDiagramJson(diagram_));
  EXPECT_EQ(MergeError({dirs[0], dir_ / "other_1"}),
            (dir_ / "other_1").string() + ": shard 2/2 of another sweep (fingerprint " + fb + ", 14 runs) than " +
                dirs[0].string() + " (fingerprint " + fa +
                ", 14 runs): it was run with another sweep file or diagram; leave it out, or run that shard again "
                "with the same files");
  EXPECT_EQ(MergeError({dirs[0], dir_}),
            dir_.string() + ": no sweep-shard.json: not the --out folder of `motionblocks sweep … --shard x/y`; give "
                            "the shard folders");
  try {
    MergeSweepShards(dirs, dirs[0]);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "--out " + dirs[0].string() + " is one of the shard folders: merge into a new folder");
  }
}

// A value edited after the shard ran is refused naming the file, the line and the run (issue 30): the manifest's
// content hash covers runs.csv, runs.json and the manifest.
TEST_F(ShardRunTest, MergeRefusesAShardEditedAfterItRan) {
  const auto dirs = RunShards(Grid(), 2, {0, 1});
  const fs::path csv = dirs[1] / "runs.csv";
  auto rows = ShardRowsOf(dirs[1]);
  ASSERT_EQ(rows[1][0], "0003");
  const std::string y = rows[1][4];  // y_final: after id, status and the two parameters
  rows[1][4] = "7.5";
  {
    const CsvTextTable table = ReadCsvTextTable(csv.string());
    std::ofstream rewrite(csv);
    rewrite << CsvLine(table.header) << "\n";
    for (const auto& row : rows) rewrite << CsvLine(row) << "\n";
  }
  const std::string error = MergeError(dirs);
  EXPECT_EQ(error.substr(0, error.find(" (content hash")),
            csv.string() + ":3: run 0003: y_final is '7.5', runs.json says '" + y +
                "' (runs.csv and runs.json disagree): changed since shard 2/2 wrote it");
  EXPECT_NE(error.find("a value was edited or the files were mixed; run the shard again into a new folder"),
            std::string::npos)
      << error;
  EXPECT_FALSE(fs::exists(dir_ / "merged" / "runs.csv"));
  // The same edit with the content hash recomputed (tests/hostile: it was merged): runs.json still disagrees.
  RewriteShard(dirs[1], rows);
  EXPECT_THAT(MergeError(dirs),
              ::testing::StartsWith(csv.string() + ":3: run 0003: y_final is '7.5', runs.json says '" + y +
                                    "' (runs.csv and runs.json disagree, though the content hash in "));
  EXPECT_FALSE(fs::exists(dir_ / "merged" / "runs.csv"));

  // The manifest edited (another description): the files are named, no row differs.
  const auto again = RunShards(Grid(), 2, {0});
  std::ifstream in(again[0] / kShardManifest);
  json manifest = json::parse(in);
  manifest["description"] = "edited";
  std::ofstream(again[0] / kShardManifest) << manifest.dump();
  EXPECT_EQ(MergeError({again[0]}).substr(0, MergeError({again[0]}).find(" (content hash")),
            (again[0] / "runs.csv").string() + ", runs.json or the manifest: changed since shard 1/2 wrote it");

  // A shard whose manifest has no content hash did not finish.
  manifest.erase(kShardContentKey);
  std::ofstream(again[0] / kShardManifest) << manifest.dump();
  EXPECT_EQ(MergeError({again[0]}), (again[0] / kShardManifest).string() +
                                        ": no \"content\" hash: shard 1/2 did not finish (interrupted), or was run by "
                                        "an older motionblocks; run it again with the same --out (it resumes) and "
                                        "merge again");
}

TEST_F(ShardRunTest, MergeRefusesAnOkRowWithANonFiniteMetric) {
  const auto dirs = RunShards(Grid(), 2, {0, 1});
  for (const std::string bad : {"nan", "inf", "-nan", "", "1e999", "x"}) {
    auto rows = ShardRowsOf(dirs[0]);
    rows[2][5] = bad;  // c_final of run 0004
    RewriteShard(dirs[0], rows);
    EXPECT_EQ(MergeError(dirs), (dirs[0] / "runs.csv").string() + ":4: run 0004 is \"ok\" but its metric c_final is '" +
                                    bad + "', not a finite number: a result that means nothing; check the diagram's "
                                          "metric, then run the shard again into a new folder");
  }
}

TEST_F(ShardRunTest, MergeRefusesConflictingDuplicateRows) {
  const auto dirs = RunShards(Grid(), 2, {0, 1});
  auto rows = ShardRowsOf(dirs[0]);
  auto retried = rows[1];  // run 0002 once more, with another y_final
  retried[4] = "123";
  rows.push_back(retried);
  RewriteShard(dirs[0], rows);
  EXPECT_EQ(MergeError(dirs), (dirs[0] / "runs.csv").string() + ":" + std::to_string(rows.size() + 1) +
                                  ": run 0002 is also on line 3 with other values: the file was edited or two runs "
                                  "were mixed; run the shard again into a new folder");
  rows.back() = rows[1];  // the same values twice: the same result
  RewriteShard(dirs[0], rows);
  EXPECT_EQ(MergeError(dirs), "no error");
}

TEST_F(ShardRunTest, MergeRefusesManifestsThatDisagree) {
  const auto halves = RunShards(Grid(), 2, {0});
  RunSweepShard(diagram_, Grid(), {1, 3}, dir_ / "third_1", options_);
  EXPECT_EQ(MergeError({halves[0], dir_ / "third_1"}),
            (dir_ / "third_1" / kShardManifest).string() + ": shard 2/3, but " +
                (halves[0] / kShardManifest).string() +
                " is shard 1/2: the shards of one merge are cut the same way (one --shard x/N); leave out the "
                "folders of the other N");
  // A copy of shard 1/2 relabelled 2/2 (its hash updated): its rows are not shard 2/2's.
  fs::copy(halves[0], dir_ / "copy", fs::copy_options::recursive);
  RewriteShard(dir_ / "copy", ShardRowsOf(dir_ / "copy"), {{"shard", 1}});
  EXPECT_EQ(MergeError({halves[0], dir_ / "copy"}),
            (dir_ / "copy" / "runs.csv").string() + ":2: run 0000 belongs to shard 1/2, but " +
                (dir_ / "copy" / kShardManifest).string() +
                " says this folder holds shard 2/2: the folder was edited or mixed; run the shard again into a new "
                "folder");
}

}  // namespace
}  // namespace mb
