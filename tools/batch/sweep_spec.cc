// Reading a sweep file (sweep_spec.h): its schema and own checks (ParseSweep with ParseGrid, ParseList, ParseRandom and
// the distributions), the runs it gives, generated on demand (SweepSpec::run: a grid's mixed-radix digits, a list's
// entries, a random sample's draws from RandomSweepSampler), and the diagram it names (SweepDiagramPath). Running the
// runs and writing runs.csv and runs.json: sweep.cc.
#include "tools/batch/sweep_spec.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/file_access.h"
#include "engine/file_error.h"
#include "engine/input_file.h"
#include "engine/json_limits.h"
#include "engine/json_parsing.h"
#include "engine/text_excerpt.h"
#include "tools/batch/sweep_schema.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string SweepRunId(std::size_t index) { return fmt::format("{:04d}", index); }

namespace {

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
  r.id = SweepRunId(index);
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
  if (error != std::errc() || end != id.data() + id.size() || SweepRunId(index) != id) return std::nullopt;
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

}  // namespace mb
