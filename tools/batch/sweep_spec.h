#pragma once
// The sweep file of `motionblocks sweep` (sweep.h) and the runs it gives: parsed and checked (ParseSweep,
// ReadSweepFile), its runs generated on demand in sweep order (SweepSpec::run; random samples by
// RandomSweepSampler), repeatable: a sweep file gives the same runs, in the same order, every time — random samples
// from their seed. Running them and writing runs.csv and runs.json: sweep.h.
//
// The sweep file (JSON), exactly one of "grid", "list", "random":
//   {
//     "description": "payload study (paper section 5.3)",           optional
//     "diagram": "../conventional.json",   optional: the diagram it was written for, relative to the sweep file
//     "set":  {"plant.friction_regularization_velocity": 0.002},    optional, applied to every run (no column)
//     "grid": {"plant.payload_mass": [0, 0.26, 0.52], "dob.cutoff_hz": [20, 30]}
//       Cartesian product; keys in alphabetical order, the last key varies fastest.
//     "list": [{"reference.velocities": [0.05], "defaultExperiment.stopTime": 15.1}, …]
//       one run per entry; a key missing from an entry keeps the diagram's value (empty cell).
//     "random": {"seed": 7, "samples": 20, "parameters": {
//         "plant.payload_mass": {"uniform": [0, 0.5]}, "dob.cutoff_hz": {"log_uniform": [10, 60]},
//         "dob.relative_degree": {"integer": [2, 3]}, "pd_p.gain": {"choice": [6000, 7000, 8000]}}}
//       `samples` draws from std::mt19937_64(seed); per draw the keys in alphabetical order, one engine() call
//       each. The uniform variate is (engine() >> 11)·2⁻⁵³, so the values do not depend on the standard library.
//       Drawn when a run is needed (RandomSweepSampler), not held: 10⁷ samples cost the memory of a few engines.
//   }
// Keys are "element.parameter" (as `--set`), or "defaultExperiment.<field>" / "solver.<field>" for the diagram's
// experiment (startTime, stopTime, stepSize) and solver sections. Values are JSON (number, string, array).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace mb {

/// One run of a sweep: its id ("0000", "0001", … in sweep order) and the values it assigns.
struct SweepRun {
  std::string id;
  std::vector<std::pair<std::string, nlohmann::json>> assignments;  ///< key → value, in column order
};

class RandomSweepSampler;

/// A parsed sweep file. Its runs are generated on demand, index → run (run(i)): a grid holds only its axes, so a
/// grid of 1000³ points costs the memory of 3000 values, not of a billion runs; a list holds its entries as
/// written; a random sample holds its distributions and draws run i when it is asked for (RandomSweepSampler:
/// the engine's state is kept at every kRandomCheckpointEvery-th draw and at a few cursors, so runs asked for in
/// order, or in a few ascending streams as parallel workers ask, cost one draw each).
struct SweepSpec {
  std::string kind;         ///< "grid", "list" or "random"
  std::string description;
  std::string diagram;      ///< "diagram" as written: relative to the sweep file (SweepDiagramPath); "" = none
  std::uint64_t seed = 0;   ///< "random" only
  std::vector<std::string> parameters;                         ///< the swept keys = the parameter columns
  std::vector<std::pair<std::string, nlohmann::json>> fixed;   ///< "set": applied to every run first

  /// How many runs the sweep has (after KeepRuns: how many it kept).
  std::size_t run_count() const;
  /// The run at `position` (0 ≤ position < run_count(), in sweep order), with its id "0000", "0001", … (its index
  /// in the whole sweep, also after KeepRuns). A grid's run is the mixed-radix digits of its index, the last key
  /// varying fastest. @throws std::out_of_range for a position ≥ run_count().
  SweepRun run(std::size_t position) const;
  /// The position of the run with id `id` ("0042"), if the sweep has it.
  std::optional<std::size_t> PositionOf(const std::string& id) const;
  /// Keeps only the runs at `positions` (ascending, each < run_count()); they keep their ids (reproduce --quick
  /// takes every other scan). @throws std::invalid_argument otherwise.
  void KeepRuns(const std::vector<std::size_t>& positions);
  /// Every value the sweep assigns, key by key in sweep order (a grid's axes, a list's cells; for a random sample
  /// each distribution's bounds, or its choices): what is checked before any run. Its size is the sum of the axes'
  /// lengths for a grid, not their product, and does not grow with a random sample's size.
  std::vector<std::pair<std::string, nlohmann::json>> AllAssignments() const;

  // How the runs are generated (ParseSweep fills these; run() reads them).
  std::vector<std::vector<nlohmann::json>> grid_axes;  ///< grid: the values of each parameter, in `parameters` order
  std::vector<std::vector<std::pair<std::string, nlohmann::json>>> entries;  ///< list: each run's values
  /// random: the sample's definition as the file gives it ({"seed", "samples", "parameters"}; what a shard's
  /// fingerprint hashes) and its sampler (shared by copies: it is immutable but for its caches, and thread-safe).
  nlohmann::json random_definition;
  std::shared_ptr<const RandomSweepSampler> sampler;
  std::vector<std::size_t> kept;  ///< KeepRuns' indices into the whole sweep (empty: every run)
};

/// The draws of a "random" sweep, run by run, without holding them: draw i is the engine's state after i·P calls
/// (P = the number of keys, one call each) from std::mt19937_64(seed), the values ParseSweep always gave.
/// Thread-safe (one mutex around the engines; a draw costs P engine calls when the runs come in ascending order per
/// worker, at most kRandomCheckpointEvery·P after a jump). Memory: one engine state (2.5 KB) per checkpoint
/// (samples / kRandomCheckpointEvery of them) and per cursor (kRandomCursors).
class RandomSweepSampler {
 public:
  struct Distribution {
    std::string kind;  ///< uniform, log_uniform, integer, choice
    double low = 0.0;
    double high = 0.0;
    nlohmann::json choices;  ///< choice: the values
  };
  RandomSweepSampler(std::uint64_t seed, std::size_t samples, std::vector<std::string> keys,
                     std::vector<Distribution> distributions);
  ~RandomSweepSampler();
  std::size_t samples() const { return samples_; }
  /// The values of draw `index` (< samples()), key → value in the keys' order. @throws std::out_of_range.
  std::vector<std::pair<std::string, nlohmann::json>> Draw(std::size_t index) const;
  /// Each distribution's extreme values (low and high; every choice): what CheckSweepSettings applies.
  std::vector<std::pair<std::string, nlohmann::json>> Extremes() const;

 private:
  struct Engines;
  std::uint64_t seed_;
  std::size_t samples_;
  std::vector<std::string> keys_;
  std::vector<Distribution> distributions_;
  std::unique_ptr<Engines> engines_;  // checkpoints and cursors, behind a mutex
};

/// A random sweep's engine state is kept every this many draws.
inline constexpr std::size_t kRandomCheckpointEvery = 4096;
/// Engine states kept where the last draws were made (one per parallel stream of ascending runs).
inline constexpr std::size_t kRandomCursors = 16;

/// Most runs a sweep may have unless the caller allows more (`sweep --max-runs`): every run's row (its values and
/// metrics, a few hundred bytes) is held in memory and gets a row in runs.csv and runs.json.
inline constexpr std::size_t kDefaultMaxSweepRuns = 100000;

/// The ceiling on any run count, whatever the caller allows: `sweep --max-runs` above it is refused, and so is a
/// shard manifest (sweep-shard.json) whose "runs" exceeds it. The draws cost nothing (RandomSweepSampler), but the
/// rows do: about 200 bytes each before the first run (SweepOutcome::rows), about 2.5 KB each by the time runs.json is
/// written (one parameter, two metrics: 100,000 runs peaked at 245 MB), so 10⁷ runs need about 25 GB; `sweep` says so
/// before it starts a sweep above kDefaultMaxSweepRuns.
inline constexpr std::size_t kMaxSweepRunsCeiling = 10000000;

/// Parses a sweep (layout above). `source` names the file in messages.
/// @throws std::invalid_argument listing every problem with its JSON pointer (none or several of grid/list/random,
/// an empty value list, a key without a '.', samples not a whole number ≥ 1, a distribution with bounds not
/// a < b, log_uniform bounds ≤ 0, an unknown distribution), or if the sweep has more than `max_runs` runs (before
/// any is built).
SweepSpec ParseSweep(const nlohmann::json& sweep, const std::string& source,
                     std::size_t max_runs = kDefaultMaxSweepRuns);

/// Reads and parses a sweep file. @throws std::runtime_error (unreadable, JSON syntax error with the byte) or
/// std::invalid_argument (as ParseSweep; JsonDepthError for nesting beyond kMaxJsonDepth).
SweepSpec ReadSweepFile(const std::filesystem::path& path, std::size_t max_runs = kDefaultMaxSweepRuns);

/// The diagram a sweep file was written for: its "diagram", resolved against the sweep file's folder (not the working
/// directory), as a diagram's file parameters are (ResolveDiagramFile): it must lie inside the sweep file's folder or a
/// folder allowed with --allow-path, and be a regular file. @throws std::invalid_argument if the sweep names none
/// ("give the diagram: motionblocks sweep DIAGRAM SWEEP"), or it lies outside (before it is opened), does not exist
/// or is no regular file.
std::filesystem::path SweepDiagramPath(const SweepSpec& spec, const std::filesystem::path& sweep_file);

/// The id of the run at `index` in the whole sweep (0-based): "0000", "0001", … (at least four digits).
std::string SweepRunId(std::size_t index);

}  // namespace mb
