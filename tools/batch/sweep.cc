#include "tools/batch/sweep.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/csv.h"
#include "engine/diagram_loader.h"
#include "engine/diagram_schema.h"
#include "engine/file_access.h"
#include "engine/file_error.h"
#include "engine/input_file.h"
#include "engine/json_limits.h"
#include "engine/json_parsing.h"
#include "engine/output_file.h"
#include "engine/text_excerpt.h"
#include "tools/batch/sweep_runner.h"
#include "tools/batch/sweep_schema.h"
#include "tools/report/output_files.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr const char* kExperimentSection = "defaultExperiment";
constexpr const char* kSolverSection = "solver";

std::string RunId(std::size_t index) { return fmt::format("{:04d}", index); }

void CheckKey(const std::string& key, const std::string& where, std::vector<std::string>* problems) {
  const auto dot = key.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == key.size()) {
    problems->push_back(fmt::format("{}: '{}': write a swept key as element.parameter (e.g. plant.payload_mass) "
                                    "or defaultExperiment.stopTime",
                                    where, key));
  }
}

// Uniform on [0, 1) from 53 random bits: the same on every standard library.
double Uniform01(std::mt19937_64& engine) {
  return static_cast<double>(engine() >> 11) * 0x1.0p-53;
}

using Distribution = RandomSweepSampler::Distribution;

// One value of `d`: exactly one engine() call (RandomSweepSampler counts on it).
json Draw(const Distribution& d, std::mt19937_64& engine) {
  const double u = Uniform01(engine);
  if (d.kind == "uniform") return d.low + (d.high - d.low) * u;
  if (d.kind == "log_uniform") return std::exp(std::log(d.low) + (std::log(d.high) - std::log(d.low)) * u);
  if (d.kind == "integer") {
    const auto lo = static_cast<long long>(d.low);
    const auto count = static_cast<long long>(d.high) - lo + 1;
    return lo + std::min(count - 1, static_cast<long long>(u * static_cast<double>(count)));
  }
  const auto n = d.choices.size();
  return d.choices[std::min(n - 1, static_cast<std::size_t>(u * static_cast<double>(n)))];
}

Distribution ParseDistribution(const json& j, const std::string& where, std::vector<std::string>* problems) {
  Distribution d;
  if (!j.is_object() || j.size() != 1) {
    problems->push_back(fmt::format("{}: write one distribution, e.g. {{\"uniform\": [0, 1]}} (uniform, "
                                    "log_uniform, integer, choice)",
                                    where));
    return d;
  }
  d.kind = j.begin().key();
  const json& v = j.begin().value();
  if (d.kind == "choice") {
    if (!v.is_array() || v.empty()) problems->push_back(fmt::format("{}/choice: give a non-empty array", where));
    d.choices = v;
    return d;
  }
  if (d.kind != "uniform" && d.kind != "log_uniform" && d.kind != "integer") {
    problems->push_back(fmt::format("{}: unknown distribution '{}' (uniform, log_uniform, integer, choice)", where,
                                    d.kind));
    return d;
  }
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
    problems->push_back(fmt::format("{}/{}: give the bounds as [low, high]", where, d.kind));
    return d;
  }
  d.low = v[0].get<double>();
  d.high = v[1].get<double>();
  if (!(d.low < d.high) && !(d.kind == "integer" && d.low == d.high)) {
    problems->push_back(fmt::format("{}/{}: bounds must satisfy low < high, got [{}, {}]", where, d.kind, d.low,
                                    d.high));
  }
  if (d.kind == "log_uniform" && !(d.low > 0.0)) {
    problems->push_back(fmt::format("{}/log_uniform: bounds must be positive, got [{}, {}]", where, d.low, d.high));
  }
  // Integers beyond 2^53 are not exact in a double, and the draw is a 64-bit integer: [0, 1e300] drew
  // −9223372036854775808 without a word (tests/hostile).
  constexpr double kMaxExactInteger = 9007199254740992.0;  // 2^53
  if (d.kind == "integer" && (std::abs(d.low) > kMaxExactInteger || std::abs(d.high) > kMaxExactInteger)) {
    problems->push_back(fmt::format("{}/integer: bounds must lie within ±2^53 (±9007199254740992), exact as numbers "
                                    "in JSON, got [{}, {}]",
                                    where, d.low, d.high));
  } else if (d.kind == "integer" && (d.low != std::floor(d.low) || d.high != std::floor(d.high))) {
    problems->push_back(fmt::format("{}/integer: bounds must be integers, got [{}, {}]", where, d.low, d.high));
  }
  return d;
}

std::vector<std::string> Header(const SweepSpec& spec, const std::vector<std::string>& metric_names) {
  std::vector<std::string> h = {"id", "status"};
  h.insert(h.end(), spec.parameters.begin(), spec.parameters.end());
  h.insert(h.end(), metric_names.begin(), metric_names.end());
  h.push_back("wall_time_s");
  h.push_back("error");
  return h;
}

// The parameter cells of a run, in column order ("" where the run does not assign the key).
std::vector<std::string> ParameterCells(const SweepSpec& spec, const SweepRun& run) {
  std::vector<std::string> cells;
  for (const auto& key : spec.parameters) {
    std::string cell;
    for (const auto& [k, v] : run.assignments) {
      if (k == key) cell = SweepValueText(v);
    }
    cells.push_back(cell);
  }
  return cells;
}

std::string RowLine(const SweepSpec& spec, const SweepRun& run, const SweepRow& row,
                    const std::vector<std::string>& metric_names) {
  std::vector<std::string> cells = {row.id, row.status};
  const auto params = ParameterCells(spec, run);
  cells.insert(cells.end(), params.begin(), params.end());
  for (const auto& m : metric_names) {
    const auto it = row.metrics.find(m);
    cells.push_back(it == row.metrics.end() ? "" : fmt::format("{:.17g}", it->second));
  }
  cells.push_back(fmt::format("{:.6f}", row.wall_time_s));
  cells.push_back(row.error);
  return CsvLine(cells);
}

// A runs.csv cell as a finite number; nullopt for anything else (nan, inf, text, trailing characters).
std::optional<double> FiniteCell(const std::string& cell) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (error != std::errc() || end != cell.data() + cell.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

// Rows recorded "ok" in an existing runs.csv, by id (the last row of an id wins: a retried run is appended).
std::map<std::string, SweepRow> ReadDoneRows(const fs::path& csv, const SweepSpec& spec,
                                            const std::vector<std::string>& metric_names) {
  std::map<std::string, SweepRow> done;
  if (!fs::exists(csv)) return done;
  const CsvTextTable table = ReadCsvTextTable(csv.string());
  if (table.header.empty()) return done;
  const auto expected = Header(spec, metric_names);
  if (table.header != expected) {
    throw std::runtime_error(fmt::format("{} has the columns [{}], this sweep writes [{}]: it was written by another "
                                         "sweep or diagram; use another --out or delete it",
                                         csv.string(), fmt::join(table.header, ", "), fmt::join(expected, ", ")));
  }
  const std::size_t first_metric = 2 + spec.parameters.size();
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto& cells = table.rows[r];
    const std::size_t line_number = table.row_lines[r];
    if (cells.size() != expected.size()) continue;  // a row cut short by an interrupted run: run it again
    const std::optional<std::size_t> position = spec.PositionOf(cells[0]);
    if (!position) {
      throw std::runtime_error(fmt::format("{}:{}: run id '{}' is not in this sweep ({} runs): written by another "
                                           "sweep; use another --out or delete it",
                                           csv.string(), line_number, Excerpt(cells[0]), spec.run_count()));
    }
    const SweepRun run = spec.run(*position);
    const auto params = ParameterCells(spec, run);
    for (std::size_t p = 0; p < params.size(); ++p) {
      if (cells[2 + p] != params[p]) {
        throw std::runtime_error(fmt::format("{}:{}: run {} has {} = {} there, but this sweep gives {}: written by "
                                             "another sweep; use another --out or delete it",
                                             csv.string(), line_number, run.id, spec.parameters[p], cells[2 + p],
                                             params[p]));
      }
    }
    if (cells[1] != "ok") {
      done.erase(run.id);
      continue;
    }
    SweepRow row;
    row.id = run.id;
    row.status = "ok";
    row.assignments = run.assignments;
    row.resumed = true;
    // A row is kept only if every metric cell reads back as a finite number (empty: a metric the run did not give):
    // a NaN or infinite metric, or an edited cell, is no result to keep; the run is run again.
    bool finite = true;
    for (std::size_t m = 0; m < metric_names.size() && finite; ++m) {
      const std::string& cell = cells[first_metric + m];
      if (cell.empty()) continue;
      const std::optional<double> value = FiniteCell(cell);
      if (value) row.metrics[metric_names[m]] = *value;
      finite = value.has_value();
    }
    const std::optional<double> wall_time = FiniteCell(cells[first_metric + metric_names.size()]);
    if (!finite || !wall_time) {
      done.erase(run.id);
      continue;
    }
    row.wall_time_s = *wall_time;
    done[run.id] = row;
  }
  return done;
}

json RowJson(const SweepRow& row) {
  json params = json::object();
  for (const auto& [k, v] : row.assignments) params[k] = v;
  json j = {{"id", row.id},           {"status", row.status},           {"parameters", params},
            {"metrics", row.metrics}, {"wall_time_s", row.wall_time_s}};
  if (!row.error.empty()) j["error"] = row.error;
  return j;
}


}  // namespace

std::string SweepValueText(const json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

namespace {

// "<what> has N runs, more than the limit …" as a problem, if n > max_runs.
bool TooManyRuns(double n, std::size_t max_runs, const std::string& what, std::vector<std::string>* problems) {
  if (n <= static_cast<double>(max_runs)) return false;
  problems->push_back(fmt::format("{} gives {:.4g} runs, more than the limit of {}: sweep fewer values (or sample "
                                  "the space with \"random\"), or raise the limit with --max-runs N",
                                  what, n, max_runs));
  return true;
}

// The runs of a "grid": the Cartesian product of the axes, the last key varying fastest.
void ParseGrid(const json& sweep, std::size_t max_runs, SweepSpec* spec, std::vector<std::string>* problems) {
  const json& grid = sweep["grid"];
  if (!grid.is_object() || grid.empty()) {
    problems->push_back("/grid: give an object {\"element.parameter\": [value, …], …}");
  } else {
    std::vector<std::vector<json>> axes;
    for (const auto& [key, values] : grid.items()) {
      CheckKey(key, "/grid", problems);
      if (!values.is_array() || values.empty()) {
        problems->push_back(fmt::format("/grid/{}: give a non-empty array of values", key));
        continue;
      }
      spec->parameters.push_back(key);
      axes.emplace_back(values.begin(), values.end());
    }
    double product = 1.0;  // in double: 1000 axes of 1000 values must not overflow
    for (const auto& a : axes) product *= static_cast<double>(a.size());
    if (problems->empty() && !TooManyRuns(product, max_runs, "/grid: the Cartesian product", problems)) {
      spec->grid_axes = std::move(axes);  // the runs are the product's points, generated by SweepSpec::run
    }
  }
}

// The runs of a "list": one per object, each with its own keys.
void ParseList(const json& sweep, std::size_t max_runs, SweepSpec* spec, std::vector<std::string>* problems) {
  const json& list = sweep["list"];
  if (list.is_array()) TooManyRuns(static_cast<double>(list.size()), max_runs, "/list", problems);
  if (!list.is_array() || list.empty()) {
    problems->push_back("/list: give a non-empty array of objects {\"element.parameter\": value, …}");
  } else {
    std::set<std::string> keys;
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_object()) {
        problems->push_back(fmt::format("/list/{}: give an object {{\"element.parameter\": value, …}}", i));
        continue;
      }
      for (const auto& [key, value] : list[i].items()) {
        CheckKey(key, fmt::format("/list/{}", i), problems);
        keys.insert(key);
      }
    }
    spec->parameters.assign(keys.begin(), keys.end());
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_object()) continue;
      std::vector<std::pair<std::string, json>> assignments;
      for (const auto& key : spec->parameters) {
        if (list[i].contains(key)) assignments.emplace_back(key, list[i][key]);
      }
      spec->entries.push_back(std::move(assignments));
    }
  }
}

// The runs of a "random" sample: `samples` draws from the distributions, reproducible from the seed.
void ParseRandom(const json& sweep, std::size_t max_runs, SweepSpec* spec, std::vector<std::string>* problems) {
  const json& random = sweep["random"];
  const json samples_json = random.is_object() ? random.value("samples", json(0)) : json(0);
  const double samples_value = samples_json.is_number() ? samples_json.get<double>() : 0.0;
  const bool whole = samples_value == std::floor(samples_value);
  const bool too_many = TooManyRuns(samples_value, max_runs, "/random/samples", problems);
  const std::size_t samples =
      whole && !too_many && samples_value >= 1.0 ? static_cast<std::size_t>(samples_value) : 0;
  if (!random.is_object() || !random.contains("seed") || !random["seed"].is_number_integer() ||
      random["seed"].get<long long>() < 0) {
    problems->push_back("/random/seed: give the seed, a non-negative integer (the same seed gives the same runs)");
  } else {
    spec->seed = random["seed"].get<std::uint64_t>();
  }
  if (samples < 1 && !too_many) problems->push_back("/random/samples: give the number of runs, a whole number >= 1");
  std::vector<Distribution> distributions;
  if (!random.contains("parameters") || !random["parameters"].is_object() || random["parameters"].empty()) {
    problems->push_back("/random/parameters: give {\"element.parameter\": {\"uniform\": [low, high]}, …}");
  } else {
    for (const auto& [key, d] : random["parameters"].items()) {
      CheckKey(key, "/random/parameters", problems);
      spec->parameters.push_back(key);
      distributions.push_back(ParseDistribution(d, "/random/parameters/" + key, problems));
    }
  }
  if (problems->empty()) {
    spec->random_definition = {{"seed", spec->seed}, {"samples", samples}, {"parameters", random["parameters"]}};
    spec->sampler = std::make_shared<const RandomSweepSampler>(spec->seed, samples, spec->parameters,
                                                               std::move(distributions));
  }
}

}  // namespace

// ---- RandomSweepSampler ------------------------------------------------------------------------------------------

struct RandomSweepSampler::Engines {
  // Where a stream of draws stands: `engine` is the state before draw `next`; the last draw made is cached (a run is
  // asked for twice in a row: to run it and to record it).
  struct Cursor {
    std::size_t next = 0;
    std::mt19937_64 engine;
    std::uint64_t last_used = 0;
    std::size_t last_index = 0;
    std::vector<std::pair<std::string, json>> last_values;
  };
  std::mutex mutex;
  std::vector<std::mt19937_64> checkpoints;  // [k]: the state before draw k·kRandomCheckpointEvery
  std::vector<Cursor> cursors;               // at most kRandomCursors
  std::uint64_t clock = 0;
};

RandomSweepSampler::RandomSweepSampler(std::uint64_t seed, std::size_t samples, std::vector<std::string> keys,
                                       std::vector<Distribution> distributions)
    : seed_(seed), samples_(samples), keys_(std::move(keys)), distributions_(std::move(distributions)),
      engines_(std::make_unique<Engines>()) {
  if (keys_.size() != distributions_.size()) {
    throw std::invalid_argument("RandomSweepSampler: one distribution per key");
  }
  engines_->checkpoints.emplace_back(seed_);
}

RandomSweepSampler::~RandomSweepSampler() = default;

std::vector<std::pair<std::string, json>> RandomSweepSampler::Draw(std::size_t index) const {
  if (index >= samples_) throw std::out_of_range(fmt::format("random sweep draw {} of {}", index, samples_));
  Engines& e = *engines_;
  std::lock_guard<std::mutex> lock(e.mutex);
  ++e.clock;
  // The cursor nearest below `index` (or holding it as its last draw), else the nearest checkpoint.
  Engines::Cursor* cursor = nullptr;
  for (auto& c : e.cursors) {
    if (c.next > 0 && c.last_index == index && c.next == index + 1) {
      c.last_used = e.clock;
      return c.last_values;
    }
    if (c.next <= index && (cursor == nullptr || c.next > cursor->next)) cursor = &c;
  }
  const std::size_t checkpoint = std::min(index / kRandomCheckpointEvery, e.checkpoints.size() - 1);
  if (cursor == nullptr || cursor->next < checkpoint * kRandomCheckpointEvery) {
    if (e.cursors.size() < kRandomCursors) {
      cursor = &e.cursors.emplace_back();
    } else {
      cursor = &*std::min_element(e.cursors.begin(), e.cursors.end(),
                                  [](const auto& a, const auto& b) { return a.last_used < b.last_used; });
    }
    cursor->engine = e.checkpoints[checkpoint];
    cursor->next = checkpoint * kRandomCheckpointEvery;
  }
  const auto keep_checkpoint = [&] {
    if (cursor->next % kRandomCheckpointEvery == 0 && cursor->next / kRandomCheckpointEvery == e.checkpoints.size()) {
      e.checkpoints.push_back(cursor->engine);
    }
  };
  for (; cursor->next < index; ++cursor->next) {
    keep_checkpoint();
    cursor->engine.discard(distributions_.size());  // one call per key
  }
  keep_checkpoint();
  std::vector<std::pair<std::string, json>> values;
  values.reserve(keys_.size());
  for (std::size_t p = 0; p < distributions_.size(); ++p) {
    values.emplace_back(keys_[p], mb::Draw(distributions_[p], cursor->engine));
  }
  cursor->next = index + 1;
  cursor->last_index = index;
  cursor->last_values = values;
  cursor->last_used = e.clock;
  return values;
}

std::vector<std::pair<std::string, json>> RandomSweepSampler::Extremes() const {
  std::vector<std::pair<std::string, json>> all;
  for (std::size_t p = 0; p < distributions_.size(); ++p) {
    const Distribution& d = distributions_[p];
    if (d.kind == "choice") {
      for (const auto& value : d.choices) all.emplace_back(keys_[p], value);
    } else if (d.kind == "integer") {
      all.emplace_back(keys_[p], static_cast<long long>(d.low));
      all.emplace_back(keys_[p], static_cast<long long>(d.high));
    } else {
      all.emplace_back(keys_[p], d.low);
      all.emplace_back(keys_[p], d.high);
    }
  }
  return all;
}

std::size_t SweepSpec::run_count() const {
  if (!kept.empty()) return kept.size();
  if (kind == "random") return sampler ? sampler->samples() : 0;
  if (kind != "grid") return entries.size();
  if (grid_axes.empty()) return 0;
  std::size_t product = 1;  // ParseSweep refused a product beyond max_runs
  for (const auto& axis : grid_axes) product *= axis.size();
  return product;
}

SweepRun SweepSpec::run(std::size_t position) const {
  if (position >= run_count()) {
    throw std::out_of_range(fmt::format("sweep run {} of {}", position, run_count()));
  }
  const std::size_t index = kept.empty() ? position : kept[position];
  SweepRun r;
  r.id = RunId(index);
  if (kind == "random") {
    r.assignments = sampler->Draw(index);
    return r;
  }
  if (kind != "grid") {
    r.assignments = entries.at(index);
    return r;
  }
  r.assignments.resize(grid_axes.size());
  std::size_t rest = index;
  for (std::size_t a = grid_axes.size(); a-- > 0;) {  // the last key varies fastest
    r.assignments[a] = {parameters[a], grid_axes[a][rest % grid_axes[a].size()]};
    rest /= grid_axes[a].size();
  }
  return r;
}

std::optional<std::size_t> SweepSpec::PositionOf(const std::string& id) const {
  std::size_t index = 0;
  const auto [end, error] = std::from_chars(id.data(), id.data() + id.size(), index);
  if (error != std::errc() || end != id.data() + id.size() || RunId(index) != id) return std::nullopt;
  if (kept.empty()) return index < run_count() ? std::optional<std::size_t>(index) : std::nullopt;
  const auto it = std::lower_bound(kept.begin(), kept.end(), index);
  if (it == kept.end() || *it != index) return std::nullopt;
  return static_cast<std::size_t>(it - kept.begin());
}

void SweepSpec::KeepRuns(const std::vector<std::size_t>& positions) {
  std::vector<std::size_t> indices;
  for (const std::size_t p : positions) {
    if (p >= run_count() || (!indices.empty() && (kept.empty() ? p : kept[p]) <= indices.back())) {
      throw std::invalid_argument(fmt::format("KeepRuns: positions must ascend and be < {}", run_count()));
    }
    indices.push_back(kept.empty() ? p : kept[p]);
  }
  kept = std::move(indices);
}

std::vector<std::pair<std::string, json>> SweepSpec::AllAssignments() const {
  std::vector<std::pair<std::string, json>> all;
  for (std::size_t a = 0; a < grid_axes.size(); ++a) {
    for (const auto& value : grid_axes[a]) all.emplace_back(parameters[a], value);
  }
  for (const auto& entry : entries) all.insert(all.end(), entry.begin(), entry.end());
  if (sampler) {
    const auto extremes = sampler->Extremes();
    all.insert(all.end(), extremes.begin(), extremes.end());
  }
  return all;
}

SweepSpec ParseSweep(const json& sweep, const std::string& source, std::size_t max_runs) {
  std::vector<std::string> problems;
  SweepSpec spec;
  if (!sweep.is_object()) throw std::invalid_argument(source + ": a sweep file is a JSON object");
  int kinds = 0;
  for (const char* k : {"grid", "list", "random"}) {
    if (sweep.contains(k)) {
      ++kinds;
      spec.kind = k;
    }
  }
  if (kinds != 1) {
    throw std::invalid_argument(fmt::format("{}: give exactly one of \"grid\", \"list\" or \"random\" (found {})",
                                            source, kinds));
  }
  // Against the schema first (unknown keys with "did you mean", types); a value of the wrong type stops here.
  const auto schema_problems = SweepSchemaProblems(sweep);
  if (std::any_of(schema_problems.begin(), schema_problems.end(), [](const auto& p) { return p.wrong_type; })) {
    throw std::invalid_argument(
        fmt::format("{}: {}", source, fmt::join(MergeProblems({}, schema_problems, false), "; ")));
  }
  spec.description = sweep.value("description", "");
  spec.diagram = sweep.value("diagram", "");
  if (sweep.contains("set")) {
    if (!sweep["set"].is_object()) problems.push_back("/set: give an object {\"element.parameter\": value}");
    for (const auto& [key, value] : sweep["set"].items()) {
      CheckKey(key, "/set", &problems);
      spec.fixed.emplace_back(key, value);
    }
  }

  if (spec.kind == "grid") {
    ParseGrid(sweep, max_runs, &spec, &problems);
  } else if (spec.kind == "list") {
    ParseList(sweep, max_runs, &spec, &problems);
  } else {
    ParseRandom(sweep, max_runs, &spec, &problems);
  }
  problems = MergeProblems(std::move(problems), schema_problems, /*own_covers_descendants=*/true);
  if (!problems.empty()) {
    throw std::invalid_argument(fmt::format("{}: {}", source, fmt::join(problems, "; ")));
  }
  return spec;
}

SweepSpec ReadSweepFile(const fs::path& path, std::size_t max_runs) {
  CheckInputFile(path, "sweep file");  // a regular file within the size limit (engine/input_file.h)
  if (!fs::exists(path)) throw FileOpenError(fmt::format("{}: cannot open the sweep file", path.string()));
  std::istringstream in(ReadInputFile(path, "sweep file"));
  json j;
  try {
    j = ParseJsonRejectingDuplicateKeys(in, path.string(), /*ignore_comments=*/false);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(
        fmt::format("{}: not valid JSON at byte {}: {}", path.string(), e.byte, JsonErrorText(e)));
  } catch (const DuplicateKeyError& e) {
    throw std::invalid_argument(fmt::format("{}: {}", path.string(), fmt::join(e.problems(), "; ")));
  }
  return ParseSweep(j, path.string(), max_runs);
}

fs::path SweepDiagramPath(const SweepSpec& spec, const fs::path& sweep_file) {
  if (spec.diagram.empty()) {
    throw std::invalid_argument(fmt::format("{}: the sweep names no \"diagram\"; give the diagram: motionblocks sweep "
                                            "DIAGRAM {}",
                                            sweep_file.string(), sweep_file.string()));
  }
  // As a diagram's own file parameters (engine/file_access.h): a sweep from someone else opens no file outside its
  // folder ("../../../../etc/passwd") unless --allow-path allows it; checked before anything is opened.
  try {
    return ResolveDiagramFile(spec.diagram, sweep_file.parent_path(), "sweep file");
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("{}: its \"diagram\" {}; or give the diagram on the command line: "
                                            "motionblocks sweep DIAGRAM {}",
                                            sweep_file.string(), e.what(), sweep_file.string()));
  }
}

json ApplySweepAssignments(json diagram, const std::vector<std::pair<std::string, json>>& assignments,
                           const std::string& source) {
  std::vector<ParameterOverride> overrides;  // "solver.step" and "defaultExperiment.stopTime" as --set takes them
  for (const auto& [key, value] : assignments) {
    const auto dot = key.find('.');
    overrides.push_back(ParameterOverride{key.substr(0, dot), key.substr(dot + 1), value});
  }
  ApplyOverrides(&diagram, overrides, source);
  return diagram;
}

namespace {

// Every element named by the sweep is checked before anything runs (DiagramError lists the elements); a misspelled
// defaultExperiment.<key> or solver.<key> would otherwise be ignored by every run.
void CheckSweepSettings(const json& base, const SweepSpec& spec, const std::string& source) {
  std::vector<std::pair<std::string, json>> all = spec.fixed;
  const auto assigned = spec.AllAssignments();
  all.insert(all.end(), assigned.begin(), assigned.end());
  // A misspelled defaultExperiment.<key> or solver.<key> would otherwise be ignored by every run.
  std::vector<std::string> problems;
  for (const auto& p : DiagramSchemaProblems(ApplySweepAssignments(base, all, source))) {
    if (p.pointer.rfind(fmt::format("/{}/", kExperimentSection), 0) == 0 ||
        p.pointer.rfind(fmt::format("/{}/", kSolverSection), 0) == 0) {
      problems.push_back(p.Text() + " (set by the sweep)");
    }
  }
  if (!problems.empty()) throw DiagramError(source, problems);
}

// Rewrites runs.csv and runs.json in sweep order (one row per run), counting the runs run now and those failed.
void WriteSweepResults(const fs::path& diagram_path, const SweepSpec& spec, const fs::path& out,
                       SweepOutcome* outcome) {
  const fs::path csv = out / "runs.csv";
  std::string text = CsvLine(Header(spec, outcome->metric_names)) + "\n";
  json rows = json::array();
  for (std::size_t i = 0; i < spec.run_count(); ++i) {
    const SweepRow& row = outcome->rows[i];
    if (!row.resumed) ++outcome->ran;
    if (row.status != "ok") ++outcome->failed;
    text += RowLine(spec, spec.run(i), row, outcome->metric_names) + "\n";
    rows.push_back(RowJson(row));
  }
  WriteFileSafely(csv, text);
  json fixed = json::object();
  for (const auto& [k, v] : spec.fixed) fixed[k] = v;
  const json summary = {{"diagram", fs::absolute(diagram_path).string()},
                        {"kind", spec.kind},
                        {"description", spec.description},
                        {"seed", spec.seed},
                        {"set", fixed},
                        {"parameters", spec.parameters},
                        {"metric_units", outcome->metric_units},
                        {"runs", rows}};
  WriteJsonFile(summary, out / "runs.json");
}

}  // namespace

struct SweepRunner::State {
  State(const fs::path& diagram, const SweepSpec& sweep, const fs::path& folder, const SweepOptions& run_options)
      : diagram_path(diagram), spec(sweep), out(folder), options(run_options), base(ReadDiagramJson(diagram)),
        source(diagram.string()) {}
  fs::path diagram_path;
  const SweepSpec& spec;
  fs::path out;
  SweepOptions options;
  json base;
  std::string source;
  SweepOutcome outcome;
  std::mutex mutex;  // guards the appended runs.csv, the progress line and the counters
  std::ofstream append;
  std::unique_ptr<ProgressLine> progress;
  std::size_t todo = 0;
  std::size_t finished = 0;
};

SweepRunner::SweepRunner(const fs::path& diagram_path, const SweepSpec& spec, const fs::path& out,
                         const SweepOptions& options)
    : state_(std::make_unique<State>(diagram_path, spec, out, options)) {
  for (const auto& m : state_->base.value("metrics", json::array())) {
    state_->outcome.metric_names.push_back(m.value("name", ""));
    state_->outcome.metric_units[m.value("name", "")] = m.value("unit", "");
  }
  CheckSweepSettings(state_->base, spec, state_->source);
}

SweepRunner::~SweepRunner() = default;

const std::vector<std::string>& SweepRunner::metric_names() const { return state_->outcome.metric_names; }

std::vector<std::size_t> SweepRunner::Start() {
  State& s = *state_;
  fs::create_directories(s.out);
  const fs::path csv = s.out / "runs.csv";
  std::map<std::string, SweepRow> done;
  if (s.options.resume) {
    done = ReadDoneRows(csv, s.spec, s.outcome.metric_names);
  } else {
    fs::remove(csv);
  }
  s.outcome.rows.resize(s.spec.run_count());
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < s.spec.run_count(); ++i) {
    const auto it = done.find(RunId(s.spec.kept.empty() ? i : s.spec.kept[i]));
    if (it != done.end()) {
      s.outcome.rows[i] = it->second;
      ++s.outcome.resumed;
    } else {
      todo.push_back(i);
    }
  }
  const bool new_file = !fs::exists(csv) || fs::file_size(csv) == 0;
  s.append.open(csv, std::ios::app);
  if (!s.append) throw std::runtime_error("cannot write " + csv.string());
  if (new_file) s.append << CsvLine(Header(s.spec, s.outcome.metric_names)) << "\n" << std::flush;
  s.todo = todo.size();
  if (s.options.progress) {
    s.progress = std::make_unique<ProgressLine>(fmt::format("sweep {} ({} runs, {} to run)",
                                                            s.diagram_path.filename().string(),
                                                            s.spec.run_count(), todo.size()));
    if (!todo.empty()) s.progress->Update(0.0);
  }
  return todo;
}

SweepRow SweepRunner::Execute(std::size_t position) const {
  const State& s = *state_;
  const SweepRun run = s.spec.run(position);
  SweepRow row;
  row.id = run.id;
  row.assignments = run.assignments;
  const auto start = std::chrono::steady_clock::now();
  try {
    json j = ApplySweepAssignments(s.base, s.spec.fixed, s.source);
    j = ApplySweepAssignments(std::move(j), run.assignments, s.source);
    const Diagram diagram =
        BuildDiagram(j, s.diagram_path.parent_path(), fmt::format("{} (sweep run {})", s.source, run.id));
    Simulator simulator(diagram);
    const SimulationResult result = simulator.Run();
    row.metrics = result.metrics;
    row.status = "ok";
    if (s.options.save_logs) {
      const fs::path dir = s.out / "runs" / run.id;
      fs::create_directories(dir);
      WriteSignalLog(result.log, dir / "signals.csv");
    }
    if (s.options.on_result) s.options.on_result(position, result);
  } catch (const std::exception& e) {
    row.status = "failed";
    row.error = e.what();
  }
  row.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return row;
}

void SweepRunner::Record(std::size_t position, SweepRow row) {
  State& s = *state_;
  std::lock_guard<std::mutex> lock(s.mutex);
  s.append << RowLine(s.spec, s.spec.run(position), row, s.outcome.metric_names) << "\n" << std::flush;
  ++s.finished;
  if (s.progress) s.progress->Update(static_cast<double>(s.finished) / static_cast<double>(s.todo));
  s.outcome.rows.at(position) = std::move(row);
}

SweepOutcome SweepRunner::Finish() {
  State& s = *state_;
  if (s.progress && s.todo > 0) s.progress->Done();
  s.append.close();
  WriteSweepResults(s.diagram_path, s.spec, s.out, &s.outcome);
  return std::move(s.outcome);
}

SweepOutcome RunSweep(const fs::path& diagram_path, const SweepSpec& spec, const fs::path& out,
                      const SweepOptions& options) {
  SweepRunner runner(diagram_path, spec, out, options);
  const std::vector<std::size_t> todo = runner.Start();
  const int jobs = options.jobs > 0 ? options.jobs
                                    : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  tbb::task_arena arena(jobs);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k != r.end(); ++k) runner.Record(todo[k], runner.Execute(todo[k]));
                      },
                      tbb::simple_partitioner());
  });
  return runner.Finish();
}

}  // namespace mb
