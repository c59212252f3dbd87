#pragma once
// Sweeps beyond one machine, on the schedulers people have (Slurm arrays, Kubernetes indexed Jobs, mpirun): a sweep
// is cut into N shards, each run anywhere as `motionblocks sweep … --shard x/N --out DIR_x` (resumable like a whole
// sweep), and `motionblocks sweep-merge DIR_1 … DIR_N --out DIR` checks that every run is there exactly once and
// writes the runs.csv the single-process sweep would have written (rows in run-id order; only wall_time_s differs).
//
// Numbering: `--shard x/y` counts from 1 (1 ≤ x ≤ y), as Jest's and Playwright's --shard do; `--shard-index K/N` and
// the schedulers' variables (`--shard auto`) count from 0 (0 ≤ K < N), as array task ids and MPI ranks do. Shard
// x/y is shard index x−1 of y. Inside (SweepShard, sweep-shard.json's "shard") the index counts from 0; messages
// name a shard as `--shard` writes it (1-based).
//
// Partition: run i (its id, the index in the whole sweep) belongs to shard i mod N (round robin). Not contiguous
// blocks: the cost of a run often grows along a grid axis (stopTime, a solver step, a payload that slows settling),
// and the keys vary in order, so contiguous blocks would give one shard all the long runs; round robin spreads every
// axis over every shard. The partition depends only on the run count, so the same file and seed always give it.
//
// Each shard folder holds sweep-shard.json: the shard index K (from 0) and N, the sweep's run count and a fingerprint of the sweep (its
// kind, seed, "set", keys and values) and of the diagram JSON (parsed, so whitespace does not count; files the
// diagram reads, such as tables, are not part of it). sweep-merge refuses folders of different fingerprints.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tools/batch/sweep.h"

namespace mb {

/// Shard index `index` (K, counted from 0) of `count` (N): 0 ≤ K < N. `--shard x/y` is {x − 1, y}.
struct SweepShard {
  std::size_t index = 0;
  std::size_t count = 1;
};

/// Looks up an environment variable: nullptr when unset (std::getenv's contract).
using EnvironmentLookup = std::function<const char*(const char*)>;

/// The shard of `--shard TEXT`: "x/y", shard x of y counted from 1 (1 ≤ x ≤ y; "1/2" and "2/2" are the two halves);
/// "auto" takes the index K (counted from 0) from SLURM_ARRAY_TASK_ID (N from SLURM_ARRAY_TASK_COUNT),
/// JOB_COMPLETION_INDEX (Kubernetes indexed Job; N must be given: "auto/N") or OMPI_COMM_WORLD_RANK (N from
/// OMPI_COMM_WORLD_SIZE), the first one set in that order; "auto/N" gives N (it must agree with the variable's).
/// @throws std::invalid_argument naming the text or variable, the numbering that applies and how to fix it (not x/y,
/// y = 0, x = 0 or x > y, no variable set, a value that is not a whole number, N missing or disagreeing).
SweepShard ParseSweepShard(const std::string& text, const EnvironmentLookup& environment = std::getenv);

/// The shard of `--shard-index TEXT`: "K/N", shard index K of N counted from 0 (0 ≤ K < N; "0/2" and "1/2" are the
/// two halves), for scripts that number from 0. @throws std::invalid_argument naming the text, the numbering and the
/// fix (not K/N, N = 0, K ≥ N).
SweepShard ParseSweepShardIndex(const std::string& text);

/// The shard `--shard` (ParseSweepShard) or else `--shard-index` (ParseSweepShardIndex) names; none (the whole
/// sweep) when both are "". @throws as those.
std::optional<SweepShard> ParseSweepShardOptions(const std::string& shard, const std::string& shard_index);

/// The shard as `--shard` writes it, counted from 1: "2/3" for index 1 of 3.
std::string ShardLabel(const SweepShard& shard);

/// The positions (= run indices of the whole sweep, from 0) of shard `shard` among `run_count` runs: K, K+N, K+2N, …
std::vector<std::size_t> ShardPositions(std::size_t run_count, const SweepShard& shard);

/// "fnv1a64:<16 hex digits>" over the sweep (kind, seed, set, keys, every run's values — for a random sample its
/// definition: seed, samples, distributions —, kept runs) and the diagram
/// JSON as parsed. Equal for the same files on any machine; the hash is not cryptographic (it catches mix-ups).
std::string SweepFingerprint(const SweepSpec& spec, const nlohmann::json& diagram);

/// The manifest file of a shard folder.
inline constexpr const char* kShardManifest = "sweep-shard.json";

/// The manifest's key for the folder's content hash (ShardContentHash), written when the shard has run (absent while
/// it runs or if it was interrupted) and checked by sweep-merge.
inline constexpr const char* kShardContentKey = "content";

/// "fnv1a64:<16 hex digits>" over `manifest` (without its "content") and the bytes of `dir`/runs.csv and
/// `dir`/runs.json: a value edited after the shard ran changes it (a check against mistakes, not a signature).
std::string ShardContentHash(nlohmann::json manifest, const std::filesystem::path& dir);

/// Runs shard `shard` of the sweep into `out` (RunSweep on ShardPositions; the runs keep their global ids) after
/// writing out/sweep-shard.json. Resumes like RunSweep when `out` holds this shard of this sweep.
/// @throws std::invalid_argument if the spec was already narrowed (KeepRuns) or the shard has no run (N > runs);
/// std::runtime_error if `out` holds another shard, another sweep, or a sweep run without --shard; as RunSweep.
SweepOutcome RunSweepShard(const std::filesystem::path& diagram, SweepSpec spec, const SweepShard& shard,
                           const std::filesystem::path& out, const SweepOptions& options = {});

struct SweepMergeOutcome {
  std::size_t runs = 0;    ///< runs in the merged runs.csv (= the sweep's run count)
  std::size_t failed = 0;  ///< of them with status "failed"
  std::size_t copied_run_folders = 0;  ///< runs/<id>/ folders copied (sweep --save-logs)
};

/// Merges shard folders into `out`: runs.csv (rows in run-id order, cells as the shards wrote them), runs.json,
/// report.html (tools/report/sweep_report.h), runs/<id>/ (if the shards saved logs) and a sweep-shard.json of shard
/// 0/1 (with its content hash). Nothing is
/// written unless every check passes. @throws std::invalid_argument naming the folder (the file and line for a row)
/// and the fix: a shard without its content hash (interrupted) or whose runs.csv, runs.json or manifest changed
/// since it ran (the first row unlike runs.json named), an "ok" row with a metric that is no finite number, one run
/// on two lines with other values, a row of another shard, manifests of another shard count or the same shard
/// index twice, no manifest, another sweep's fingerprint,
/// other columns, `out` among the inputs, runs missing or present twice (the first 10 ids listed, with their shard),
/// a shard's runs.json behind its runs.csv (interrupted: run the shard again), a manifest whose "runs" is not a whole
/// number of at most kMaxSweepRunsCeiling or whose "shards" is not a whole number from 1 to "runs" (naming the file
/// and the key).
SweepMergeOutcome MergeSweepShards(const std::vector<std::filesystem::path>& shards, const std::filesystem::path& out);

}  // namespace mb
