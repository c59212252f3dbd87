// Which shard of a sweep a process runs (shard.h): --shard K/N (counted from 1), --shard-index K/N (from 0) and
// --shard auto[/N] from the scheduler's variables, from whichever option is given; the shard's label and its runs'
// positions.
#include "tools/batch/shard.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "engine/text_excerpt.h"
#include "tools/batch/whole_number.h"

namespace mb {

namespace {

std::size_t EnvironmentNumber(const char* name, const char* value) {
  const auto n = WholeNumber(value);
  if (!n) {
    throw std::invalid_argument(
        fmt::format("--shard auto: {}='{}' is not a whole number >= 0", name, Excerpt(value)));
  }
  return *n;
}

// --shard auto[/N]: K (and N) from the first scheduler variable set.
SweepShard ShardFromEnvironment(std::optional<std::size_t> given_count, const EnvironmentLookup& environment) {
  struct Source {
    const char* index;
    const char* count;  // nullptr: the scheduler does not export N
    const char* fix;
  };
  const Source sources[] = {
      {"SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "submit the array as --array=0-{last}"},
      {"JOB_COMPLETION_INDEX", nullptr, "write --shard auto/N with N = the Job's completions"},
      {"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "start {count} processes"}};
  for (const Source& s : sources) {
    const char* index_text = environment(s.index);
    if (index_text == nullptr) continue;
    SweepShard shard;
    shard.index = EnvironmentNumber(s.index, index_text);
    const char* count_text = s.count != nullptr ? environment(s.count) : nullptr;
    if (count_text == nullptr && !given_count) {
      throw std::invalid_argument(fmt::format("--shard auto: {}={} gives K but nothing gives N: write --shard auto/N "
                                              "(N = the number of shards)",
                                              s.index, shard.index));
    }
    shard.count = given_count.value_or(0);
    if (count_text != nullptr) {
      const std::size_t count = EnvironmentNumber(s.count, count_text);
      if (given_count && *given_count != count) {
        throw std::invalid_argument(fmt::format("--shard auto/{}: {}={} says {} shards: give --shard auto or auto/{}",
                                                *given_count, s.count, count, count, count));
      }
      shard.count = count;
    }
    if (shard.count == 0) throw std::invalid_argument("--shard auto: the number of shards N must be at least 1");
    if (shard.index >= shard.count) {
      throw std::invalid_argument(fmt::format("--shard auto: {}={} but there are {} shards (numbered 0 to {}): {}",
                                              s.index, shard.index, shard.count, shard.count - 1,
                                              fmt::format(fmt::runtime(s.fix), fmt::arg("last", shard.count - 1),
                                                          fmt::arg("count", shard.count))));
    }
    return shard;
  }
  throw std::invalid_argument(
      "--shard auto: none of SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX, OMPI_COMM_WORLD_RANK is set: run it as a "
      "Slurm array task, a Kubernetes indexed Job or under mpirun, or give the shard as x/y (counted from 1)");
}

// "A/B" as two whole numbers; nullopt for either part that is not one (B is nullopt without a '/').
std::pair<std::optional<std::size_t>, std::optional<std::size_t>> Fraction(const std::string& text,
                                                                           std::string* first) {
  const auto slash = text.find('/');
  *first = text.substr(0, slash);
  return {WholeNumber(*first), slash == std::string::npos ? std::nullopt : WholeNumber(text.substr(slash + 1))};
}

constexpr const char* kOtherNumbering = "--shard-index K/N counts from 0 (0 <= K < N)";

}  // namespace

SweepShard ParseSweepShard(const std::string& text, const EnvironmentLookup& environment) {
  std::string first;
  const auto [x, y] = Fraction(text, &first);
  const std::string usage =
      fmt::format("--shard '{}': write x/y, shard x of y counted from 1 (1 <= x <= y, e.g. 1/4 to 4/4, as Jest and "
                  "Playwright count), or auto or auto/N (index from the scheduler, counted from 0); {}",
                  Excerpt(text), kOtherNumbering);
  const bool has_slash = text.find('/') != std::string::npos;
  if (has_slash && !y) throw std::invalid_argument(usage);
  if (y && *y == 0) throw std::invalid_argument(fmt::format("--shard {}: the number of shards must be at least 1", text));
  if (first == "auto") return ShardFromEnvironment(y, environment);
  if (!x || !y) throw std::invalid_argument(usage);
  if (*x == 0 || *x > *y) {
    throw std::invalid_argument(fmt::format("--shard {}: --shard x/y counts from 1, so x runs from 1 to {} (write "
                                            "--shard 1/{} … {}/{}); {}",
                                            text, *y, *y, *y, *y, kOtherNumbering));
  }
  return SweepShard{*x - 1, *y};
}

SweepShard ParseSweepShardIndex(const std::string& text) {
  std::string first;
  const auto [k, n] = Fraction(text, &first);
  if (!k || !n) {
    throw std::invalid_argument(fmt::format("--shard-index '{}': write K/N, shard index K of N counted from 0 "
                                            "(0 <= K < N, e.g. 0/4 to 3/4); --shard x/y counts from 1",
                                            Excerpt(text)));
  }
  if (*n == 0) {
    throw std::invalid_argument(fmt::format("--shard-index {}: the number of shards must be at least 1", text));
  }
  if (*k >= *n) {
    throw std::invalid_argument(fmt::format("--shard-index {}: --shard-index counts from 0, so K runs from 0 to {} "
                                            "(write --shard-index 0/{} … {}/{}); --shard x/y counts from 1 (1 <= x "
                                            "<= y)",
                                            text, *n - 1, *n, *n - 1, *n));
  }
  return SweepShard{*k, *n};
}

std::optional<SweepShard> ParseSweepShardOptions(const std::string& shard, const std::string& shard_index) {
  if (!shard.empty()) return ParseSweepShard(shard);
  if (!shard_index.empty()) return ParseSweepShardIndex(shard_index);
  return std::nullopt;
}

std::string ShardLabel(const SweepShard& shard) { return fmt::format("{}/{}", shard.index + 1, shard.count); }

std::vector<std::size_t> ShardPositions(std::size_t run_count, const SweepShard& shard) {
  std::vector<std::size_t> positions;
  for (std::size_t i = shard.index; i < run_count; i += shard.count) positions.push_back(i);
  return positions;
}

}  // namespace mb
