#pragma once
// "Did you mean" for registries (block types, catalogue effects): the known names closest to a misspelt one.
// Header-only so that libraries without the engine (models/diagnosis) use the same rule.

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mb {

/// Levenshtein distance (insertions, deletions, substitutions of bytes).
inline std::size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0u : 1u)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

/// Up to `max_suggestions` of `known`, closest to `name` first, within an edit distance of max(3, |name|/2).
inline std::vector<std::string> ClosestNames(std::string_view name, const std::vector<std::string>& known,
                                             std::size_t max_suggestions = 3) {
  std::vector<std::pair<std::size_t, std::string>> scored;
  for (const auto& k : known) scored.emplace_back(EditDistance(name, k), k);
  std::sort(scored.begin(), scored.end());
  std::vector<std::string> out;
  for (const auto& [d, k] : scored) {
    if (out.size() >= max_suggestions || d > std::max<std::size_t>(3, name.size() / 2)) break;
    out.push_back(k);
  }
  return out;
}

}  // namespace mb
