#pragma once
// A whole number as the shards write it (shard.h): --shard x/y and --shard-index K/N, the schedulers' variables
// (shard_selection.cc), and the run ids of a shard's runs.csv when sweep-merge reads them (shard.cc).

#include <charconv>
#include <cstddef>
#include <optional>
#include <string>
#include <system_error>

namespace mb {

/// `text` as a whole number: the whole text decimal digits, within std::size_t; none for anything else ("", "-1",
/// "+1", " 1", "1.5", a number too large).
inline std::optional<std::size_t> WholeNumber(const std::string& text) {
  std::size_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace mb
