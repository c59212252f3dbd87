#include "tools/batch/shard.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/csv.h"
#include "engine/diagram_loader.h"
#include "engine/input_file.h"
#include "engine/output_file.h"
#include "engine/text_excerpt.h"
#include "tools/batch/whole_number.h"
#include "tools/report/output_files.h"
#include "tools/report/sweep_report.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr std::size_t kListedIds = 10;  // ids named in a merge error; the rest are counted

// FNV-1a, 64 bits (Fowler, Noll, Vo; http://www.isthe.com/chongo/tech/comp/fnv/).
std::uint64_t Fnv1a64(const std::string& text) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

}  // namespace

std::string SweepFingerprint(const SweepSpec& spec, const json& diagram) {
  json grid = json::array();
  for (const auto& axis : spec.grid_axes) grid.push_back(axis);
  json entries = json::array();
  for (const auto& entry : spec.entries) entries.push_back(entry);
  json canonical = {{"kind", spec.kind},         {"seed", spec.seed},   {"set", spec.fixed},
                    {"parameters", spec.parameters}, {"grid", grid},   {"entries", entries},
                    {"kept", spec.kept},         {"diagram", diagram}};
  // A random sample is drawn run by run, not held (RandomSweepSampler): its definition (seed, samples,
  // distributions) stands for its draws. Grids and lists hash as they always did.
  if (spec.kind == "random") canonical["random"] = spec.random_definition;
  return fmt::format("fnv1a64:{:016x}", Fnv1a64(canonical.dump()));
}

namespace {

// The counts of a manifest are bounded before anything loops over them: "runs" is a whole number from 1 to
// kMaxSweepRunsCeiling, "shards" one from 1 to "runs", "shard" less than "shards". @throws std::invalid_argument
// naming the file, the key and its value.
void CheckManifestCounts(const json& j, const fs::path& path) {
  const auto bad = [&](const char* key, const std::string& what) {
    return std::invalid_argument(fmt::format("{}: \"{}\": {} is not {}: the manifest was edited or damaged; delete "
                                             "the folder and run the shard again",
                                             path.string(), key, j[key].dump(), what));
  };
  const auto whole = [&](const char* key) { return j[key].is_number_unsigned(); };
  if (!whole("runs") || j["runs"].get<std::uint64_t>() < 1 || j["runs"].get<std::uint64_t>() > kMaxSweepRunsCeiling) {
    throw bad("runs", fmt::format("a run count from 1 to {} (the most runs a sweep may have)", kMaxSweepRunsCeiling));
  }
  if (!whole("shards") || j["shards"].get<std::uint64_t>() < 1 ||
      j["shards"].get<std::uint64_t>() > j["runs"].get<std::uint64_t>()) {
    throw bad("shards", fmt::format("a shard count from 1 to \"runs\" ({})", j["runs"].get<std::uint64_t>()));
  }
  if (!whole("shard") || j["shard"].get<std::uint64_t>() >= j["shards"].get<std::uint64_t>()) {
    throw bad("shard", fmt::format("a shard index from 0 to \"shards\" - 1 ({})", j["shards"].get<std::uint64_t>() - 1));
  }
}

// Whether `path` names anything (a missing file is no error for the readers below; a FIFO or device is one, refused
// by ReadInputFile before it is opened: a manifest that is a FIFO with no writer would block sweep-merge forever).
bool Exists(const fs::path& path) {
  std::error_code error;
  return fs::exists(path, error);
}

json ReadManifest(const fs::path& dir) {
  const fs::path path = dir / kShardManifest;
  if (!Exists(path)) return nullptr;
  const std::string text = ReadInputFile(path, "shard manifest");
  try {
    json j = json::parse(text);
    if (j.is_object() && j.value("fingerprint", json()).is_string() && j.value("shard", json()).is_number() &&
        j.value("shards", json()).is_number() && j.value("runs", json()).is_number()) {
      CheckManifestCounts(j, path);
      return j;
    }
  } catch (const json::parse_error&) {
  }
  throw std::invalid_argument(fmt::format("{}: not a shard manifest (fingerprint, shard, shards, runs): delete the "
                                          "folder and run the shard again",
                                          path.string()));
}

// The manifest's shard as `--shard` writes it (counted from 1).
std::string ShardText(const json& manifest) {
  return ShardLabel({manifest["shard"].get<std::size_t>(), manifest["shards"].get<std::size_t>()});
}

// out may hold this shard of this sweep (resume), nothing, or an empty folder; anything else is refused.
void CheckShardFolder(const fs::path& out, const json& manifest) {
  const json old = ReadManifest(out);
  if (old.is_null()) {
    if (fs::exists(out / "runs.csv")) {
      throw std::runtime_error(fmt::format("{}: holds a sweep run without --shard (runs.csv, no {}): use another "
                                           "--out for the shard",
                                           out.string(), kShardManifest));
    }
    return;
  }
  if (old["fingerprint"] != manifest["fingerprint"]) {
    throw std::runtime_error(fmt::format("{}: holds shard {} of another sweep (fingerprint {}, this sweep and diagram "
                                         "give {}): use another --out, or delete the folder to start over",
                                         out.string(), ShardText(old), old["fingerprint"].get<std::string>(),
                                         manifest["fingerprint"].get<std::string>()));
  }
  if (old["shard"] != manifest["shard"] || old["shards"] != manifest["shards"]) {
    throw std::runtime_error(fmt::format("{}: holds shard {} of this sweep, not {}: give --shard {} to resume it, or "
                                         "use another --out",
                                         out.string(), ShardText(old), ShardText(manifest), ShardText(old)));
  }
}

// The bytes of `path`, or "" if there is no such file. A FIFO, a device or a folder is refused before it is opened;
// no size limit: the shard's own runs.json of a long sweep may exceed the input limit and is hashed all the same.
std::string FileBytes(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) return {};
  if (!fs::is_regular_file(status)) {
    throw std::invalid_argument(fmt::format("{}: not a regular file (a FIFO, a device or a folder): a shard folder "
                                            "holds the files its sweep wrote; run the shard again into a new folder",
                                            path.string()));
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// Writes the manifest with its content hash (ShardContentHash) once the folder's runs.csv and runs.json are final.
void SealShardFolder(json manifest, const fs::path& dir) {
  manifest[kShardContentKey] = ShardContentHash(manifest, dir);
  WriteJsonFile(manifest, dir / kShardManifest);
}

}  // namespace

std::string ShardContentHash(json manifest, const fs::path& dir) {
  manifest.erase(kShardContentKey);
  const std::string text = manifest.dump() + "\n" + FileBytes(dir / "runs.csv") + "\n" + FileBytes(dir / "runs.json");
  return fmt::format("fnv1a64:{:016x}", Fnv1a64(text));
}

SweepOutcome RunSweepShard(const fs::path& diagram, SweepSpec spec, const SweepShard& shard, const fs::path& out,
                           const SweepOptions& options) {
  if (!spec.kept.empty()) throw std::invalid_argument("RunSweepShard: shard the whole sweep, not one narrowed by KeepRuns");
  if (shard.count == 0 || shard.index >= shard.count) {
    throw std::invalid_argument(fmt::format("shard index {} of {}: the index counts from 0 and must be less than the "
                                            "number of shards",
                                            shard.index, shard.count));
  }
  const std::size_t runs = spec.run_count();
  if (shard.index >= runs) {
    throw std::invalid_argument(fmt::format("--shard {}: the sweep has {} runs, so this shard has none: use at "
                                            "most {} shards",
                                            ShardLabel(shard), runs, runs));
  }
  const json manifest = {{"fingerprint", SweepFingerprint(spec, ReadDiagramJson(diagram))},
                         {"shard", shard.index},
                         {"shards", shard.count},
                         {"runs", runs},
                         {"partition", "run i belongs to shard index i mod shards (counted from 0; --shard x/y is index x-1)"},
                         {"diagram", fs::absolute(diagram).string()},
                         {"description", spec.description}};
  CheckShardFolder(out, manifest);
  fs::create_directories(out);
  WriteJsonFile(manifest, out / kShardManifest);  // no "content" yet: an interrupted shard is not mergeable
  spec.KeepRuns(ShardPositions(runs, shard));
  SweepOutcome outcome = RunSweep(diagram, spec, out, options);
  SealShardFolder(manifest, out);
  return outcome;
}

namespace {

struct ShardRows {
  fs::path dir;
  json manifest;
  CsvTextTable table;
  std::map<std::size_t, std::size_t> rows;  // run index → row of table (one row per run; equal repeats allowed)
};

// The shard's runs.json as written, or an empty object.
json ReadRunsJson(const fs::path& dir) {
  const std::string text = FileBytes(dir / "runs.json");
  json j = text.empty() ? json() : json::parse(text, nullptr, /*allow_exceptions=*/false);
  return j.is_object() ? j : json::object();
}

// Each row belongs to the manifest's shard (run i to shard index i mod N), and an "ok" row has a finite number in
// every metric column (between the parameters, as the shard's runs.json lists them, and wall_time_s).
void CheckShardRows(const ShardRows& shard) {
  const std::size_t k = shard.manifest["shard"].get<std::size_t>(), n = shard.manifest["shards"].get<std::size_t>();
  const json runs_json = ReadRunsJson(shard.dir);
  const std::size_t parameters = runs_json.value("parameters", json::array()).size();
  const auto& header = shard.table.header;
  for (const auto& [index, r] : shard.rows) {
    const auto& cells = shard.table.rows[r];
    const std::size_t line = shard.table.row_lines[r];
    if (index % n != k) {
      throw std::invalid_argument(fmt::format("{}:{}: run {} belongs to shard {}, but {} says this folder holds shard "
                                              "{}: the folder was edited or mixed; run the shard again into a new "
                                              "folder",
                                              shard.table.source, line, cells[0], ShardLabel({index % n, n}),
                                              (shard.dir / kShardManifest).string(), ShardText(shard.manifest)));
    }
    if (cells.size() < 2 || cells[1] != "ok") continue;
    for (std::size_t c = 2 + parameters; c + 2 < header.size() && c < cells.size(); ++c) {
      double value = 0.0;
      const std::string& cell = cells[c];
      const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
      if (cell.empty() || error != std::errc() || end != cell.data() + cell.size() || !std::isfinite(value)) {
        throw std::invalid_argument(fmt::format("{}:{}: run {} is \"ok\" but its metric {} is '{}', not a finite "
                                                "number: a result that means nothing; check the diagram's metric, "
                                                "then run the shard again into a new folder",
                                                shard.table.source, line, cells[0], Excerpt(header[c]),
                                                Excerpt(cell)));
      }
    }
  }
}

// The first row of runs.csv whose status or metrics differ from its runs.json row, as "file:line: …"; "" if none.
std::string FirstRowUnlikeRunsJson(const ShardRows& shard) {
  const json runs_json = ReadRunsJson(shard.dir);
  std::map<std::string, json> by_id;
  for (const auto& row : runs_json.value("runs", json::array())) {
    if (row.is_object()) by_id[row.value("id", "")] = row;
  }
  const std::size_t parameters = runs_json.value("parameters", json::array()).size();
  const auto& header = shard.table.header;
  for (const auto& [index, r] : shard.rows) {
    const auto& cells = shard.table.rows[r];
    const auto line = shard.table.row_lines[r];  // not the binding itself: clang 14 cannot capture one
    const auto where = [&](const std::string& what) {
      return fmt::format("{}:{}: run {}: {}", shard.table.source, line, cells[0], what);
    };
    const auto it = by_id.find(cells[0]);
    if (it == by_id.end()) return where("not in runs.json");
    const json& row = it->second;
    if (cells.size() > 1 && row.value("status", "") != cells[1]) {
      return where(fmt::format("status '{}', runs.json says '{}'", Excerpt(cells[1]), row.value("status", "")));
    }
    for (std::size_t c = 2 + parameters; c + 2 < header.size() && c < cells.size(); ++c) {
      const json metric = row.value("metrics", json::object()).value(header[c], json());
      const std::string written = metric.is_number() ? fmt::format("{:.17g}", metric.get<double>()) : "";
      if (written != cells[c]) {
        return where(fmt::format("{} is '{}', runs.json says '{}'", Excerpt(header[c]), Excerpt(cells[c]), written));
      }
    }
  }
  return {};
}

// The folder's runs.csv, runs.json and manifest are as the shard wrote them: the manifest's "content" hash
// (ShardContentHash) matches. Naming the first row that differs from runs.json when one does.
void CheckShardContent(const ShardRows& shard) {
  const fs::path manifest = shard.dir / kShardManifest;
  const json recorded = shard.manifest.value(kShardContentKey, json());
  if (!recorded.is_string()) {
    throw std::invalid_argument(fmt::format("{}: no \"{}\" hash: shard {} did not finish (interrupted), or was run "
                                            "by an older motionblocks; run it again with the same --out (it resumes) "
                                            "and merge again",
                                            manifest.string(), kShardContentKey, ShardText(shard.manifest)));
  }
  const std::string now = ShardContentHash(shard.manifest, shard.dir);
  const std::string row = FirstRowUnlikeRunsJson(shard);
  if (recorded.get<std::string>() == now && row.empty()) return;
  if (recorded.get<std::string>() == now) {  // the hash recomputed after an edit of runs.csv alone (tests/hostile)
    throw std::invalid_argument(fmt::format("{} (runs.csv and runs.json disagree, though the content hash in {} "
                                            "matches: it was recomputed after an edit); run the shard again into a "
                                            "new folder",
                                            row, manifest.string()));
  }
  throw std::invalid_argument(fmt::format("{}{}: changed since shard {} wrote it (content hash {} recorded in {}, {} "
                                          "now): a value was edited or the files were mixed; run the shard again "
                                          "into a new folder",
                                          row.empty() ? (shard.dir / "runs.csv").string() + ", runs.json or the manifest"
                                                      : row,
                                          row.empty() ? "" : " (runs.csv and runs.json disagree)",
                                          ShardText(shard.manifest), recorded.get<std::string>(), manifest.string(),
                                          now));
}

ShardRows ReadShard(const fs::path& dir) {
  ShardRows shard{dir, ReadManifest(dir), {}, {}};
  if (shard.manifest.is_null()) {
    throw std::invalid_argument(fmt::format("{}: no {}: not the --out folder of `motionblocks sweep … --shard x/y`; "
                                            "give the shard folders",
                                            dir.string(), kShardManifest));
  }
  if (!fs::exists(dir / "runs.csv")) {
    throw std::invalid_argument(fmt::format("{}: no runs.csv: shard {} has not run; run it (sweep … --shard {} --out "
                                            "{}) and merge again",
                                            dir.string(), ShardText(shard.manifest), ShardText(shard.manifest),
                                            dir.string()));
  }
  shard.table = ReadCsvTextTable((dir / "runs.csv").string());
  const std::size_t runs = shard.manifest["runs"].get<std::size_t>();
  for (std::size_t r = 0; r < shard.table.rows.size(); ++r) {
    const auto& cells = shard.table.rows[r];
    if (cells.size() != shard.table.header.size()) continue;  // cut short by an interrupted run: missing
    const auto index = WholeNumber(cells[0]);
    if (!index || *index >= runs || fmt::format("{:04d}", *index) != cells[0]) {
      throw std::invalid_argument(fmt::format("{}:{}: run id '{}' is not one of the sweep's {} runs: the folder was "
                                              "edited or mixed; run the shard again into a new folder",
                                              shard.table.source, shard.table.row_lines[r], Excerpt(cells[0]), runs));
    }
    const auto [it, inserted] = shard.rows.emplace(*index, r);
    if (!inserted && shard.table.rows[it->second] != cells) {
      throw std::invalid_argument(fmt::format("{}:{}: run {} is also on line {} with other values: the file was edited "
                                              "or two runs were mixed; run the shard again into a new folder",
                                              shard.table.source, shard.table.row_lines[r], cells[0],
                                              shard.table.row_lines[it->second]));
    }
  }
  CheckShardRows(shard);
  CheckShardContent(shard);
  return shard;
}

// Every folder from the sweep of the first, with the same columns; `out` not among them.
void CheckSameSweep(const std::vector<ShardRows>& shards, const fs::path& out) {
  const ShardRows& first = shards.front();
  for (const ShardRows& s : shards) {
    if (fs::exists(out) && fs::equivalent(s.dir, out)) {
      throw std::invalid_argument(fmt::format("--out {} is one of the shard folders: merge into a new folder",
                                              out.string()));
    }
    if (s.manifest["fingerprint"] != first.manifest["fingerprint"] || s.manifest["runs"] != first.manifest["runs"]) {
      throw std::invalid_argument(fmt::format(
          "{}: shard {} of another sweep (fingerprint {}, {} runs) than {} (fingerprint {}, {} runs): it was run with "
          "another sweep file or diagram; leave it out, or run that shard again with the same files",
          s.dir.string(), ShardText(s.manifest), s.manifest["fingerprint"].get<std::string>(),
          s.manifest["runs"].get<std::size_t>(), first.dir.string(), first.manifest["fingerprint"].get<std::string>(),
          first.manifest["runs"].get<std::size_t>()));
    }
    if (s.manifest["shards"] != first.manifest["shards"]) {
      throw std::invalid_argument(fmt::format("{}: shard {}, but {} is shard {}: the shards of one merge are cut the "
                                              "same way (one --shard x/N); leave out the folders of the other N",
                                              (s.dir / kShardManifest).string(), ShardText(s.manifest),
                                              (first.dir / kShardManifest).string(), ShardText(first.manifest)));
    }
    for (const ShardRows& other : shards) {
      if (&other == &s) break;
      if (other.manifest["shard"] == s.manifest["shard"]) {
        throw std::invalid_argument(fmt::format("{} and {} both say they hold shard {}: give each shard's folder once "
                                                "(a folder copied or run twice)",
                                                (other.dir / kShardManifest).string(),
                                                (s.dir / kShardManifest).string(), ShardText(s.manifest)));
      }
    }
    if (s.table.header != first.table.header) {
      throw std::invalid_argument(fmt::format("{}/runs.csv has the columns [{}], {}/runs.csv [{}]: run the shard again "
                                              "into a new folder",
                                              s.dir.string(), fmt::join(s.table.header, ", "), first.dir.string(),
                                              fmt::join(first.table.header, ", ")));
    }
  }
}

std::string ListIds(const std::vector<std::string>& ids) {
  const std::size_t shown = std::min(ids.size(), kListedIds);
  std::string text = fmt::format("{}", fmt::join(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(shown), ", "));
  if (ids.size() > shown) text += fmt::format(" and {} more", ids.size() - shown);
  return text;
}

// run index → (shard, row); throws listing the runs present twice and those missing.
std::map<std::size_t, std::pair<const ShardRows*, std::size_t>> CollectRuns(const std::vector<ShardRows>& shards) {
  std::map<std::size_t, std::pair<const ShardRows*, std::size_t>> runs;
  std::vector<std::string> duplicates;
  for (const ShardRows& s : shards) {
    for (const auto& [index, row] : s.rows) {
      const auto [it, inserted] = runs.emplace(index, std::make_pair(&s, row));
      if (!inserted) {
        duplicates.push_back(fmt::format("{:04d} ({} and {})", index, it->second.first->dir.string(), s.dir.string()));
      }
    }
  }
  if (!duplicates.empty()) {
    throw std::invalid_argument(fmt::format("{} runs are in two shard folders: {}: give each shard's folder once (a "
                                            "folder given twice, or shards of two different --shard N)",
                                            duplicates.size(), ListIds(duplicates)));
  }
  const std::size_t count = shards.front().manifest["runs"].get<std::size_t>();
  const std::size_t n = shards.front().manifest["shards"].get<std::size_t>();
  std::vector<std::string> missing;
  for (std::size_t i = 0; i < count; ++i) {
    if (runs.count(i) == 0) missing.push_back(fmt::format("{:04d} (shard {})", i, ShardLabel({i % n, n})));
  }
  if (!missing.empty()) {
    throw std::invalid_argument(fmt::format("{} of {} runs are missing: {}: run their shard again with the same --out "
                                            "(it resumes) or add its folder, then merge again",
                                            missing.size(), count, ListIds(missing)));
  }
  return runs;
}

// The shards' runs.json rows by id; a shard whose runs.json lacks a row of its runs.csv was interrupted.
json MergedRunsJson(const std::vector<ShardRows>& shards,
                    const std::map<std::size_t, std::pair<const ShardRows*, std::size_t>>& runs) {
  std::map<const ShardRows*, std::map<std::string, json>> by_shard;
  json merged;
  for (const ShardRows& s : shards) {
    const std::string text = FileBytes(s.dir / "runs.json");
    json j = text.empty() ? json() : json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object() || !j.value("runs", json()).is_array()) j = json{{"runs", json::array()}};
    for (const auto& row : j["runs"]) by_shard[&s][row.value("id", "")] = row;
    if (merged.is_null()) merged = j;
  }
  merged["runs"] = json::array();
  for (const auto& [index, where] : runs) {
    const std::string id = fmt::format("{:04d}", index);
    const auto& rows = by_shard[where.first];
    const auto it = rows.find(id);
    if (it == rows.end()) {
      throw std::invalid_argument(fmt::format("{}/runs.json lacks run {} of its runs.csv: the shard was interrupted; "
                                              "run it again with the same --out (it resumes) and merge again",
                                              where.first->dir.string(), id));
    }
    merged["runs"].push_back(it->second);
  }
  return merged;
}

}  // namespace

SweepMergeOutcome MergeSweepShards(const std::vector<fs::path>& dirs, const fs::path& out) {
  if (dirs.empty()) throw std::invalid_argument("sweep-merge: give the shard folders");
  std::vector<ShardRows> shards;
  for (const fs::path& dir : dirs) shards.push_back(ReadShard(dir));
  CheckSameSweep(shards, out);
  const auto runs = CollectRuns(shards);
  const json runs_json = MergedRunsJson(shards, runs);

  SweepMergeOutcome outcome;
  std::string text = CsvLine(shards.front().table.header) + "\n";
  for (const auto& [index, where] : runs) {
    const auto& cells = where.first->table.rows[where.second];
    text += CsvLine(cells) + "\n";
    ++outcome.runs;
    if (cells[1] != "ok") ++outcome.failed;
  }
  fs::create_directories(out);
  for (const auto& [index, where] : runs) {
    const std::string id = fmt::format("{:04d}", index);
    const fs::path from = where.first->dir / "runs" / id;
    if (!fs::is_directory(from)) continue;
    fs::create_directories(out / "runs" / id);
    fs::copy(from, out / "runs" / id, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    ++outcome.copied_run_folders;
  }
  WriteFileSafely(out / "runs.csv", text);
  WriteJsonFile(runs_json, out / "runs.json");
  WriteSweepReport(out, runs_json);  // the merged sweep's picture, as one process would have drawn it
  json manifest = shards.front().manifest;
  manifest["shard"] = 0;
  manifest["shards"] = 1;
  manifest["merged_from"] = json::array();
  for (const fs::path& dir : dirs) manifest["merged_from"].push_back(fs::absolute(dir).string());
  SealShardFolder(manifest, out);
  return outcome;
}

}  // namespace mb
