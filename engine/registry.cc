#include "engine/registry.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace mb {

BlockRegistry& BlockRegistry::Global() {
  static BlockRegistry registry;
  return registry;
}

bool BlockRegistry::Add(BlockType type) {
  const std::string name = type.type_name;
  if (!types_.emplace(name, std::move(type)).second) {
    throw std::logic_error(fmt::format("block type '{}' registered twice", name));
  }
  return true;
}

const BlockType* BlockRegistry::Find(const std::string& type_name) const {
  auto it = types_.find(type_name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> BlockRegistry::TypeNames() const {
  std::vector<std::string> names;
  for (const auto& [name, type] : types_) names.push_back(name);
  return names;
}

const BlockType& BlockRegistry::SumOfTwo() const {
  for (const auto& [name, type] : types_) {
    if (type.sum_of_two) return type;
  }
  throw std::logic_error("no registered block type adds two signals (sum_of_two): link mb_blocks into the program");
}

namespace {
std::size_t EditDistance(const std::string& a, const std::string& b) {
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
}  // namespace

std::vector<std::string> ClosestNames(const std::string& name, const std::vector<std::string>& candidates,
                                      std::size_t max_suggestions) {
  std::vector<std::pair<std::size_t, std::string>> scored;
  for (const auto& candidate : candidates) scored.emplace_back(EditDistance(name, candidate), candidate);
  std::sort(scored.begin(), scored.end());
  std::vector<std::string> out;
  for (const auto& [d, candidate] : scored) {
    if (out.size() >= max_suggestions || d > std::max<std::size_t>(3, name.size() / 2)) break;
    out.push_back(candidate);
  }
  return out;
}

std::vector<std::string> BlockRegistry::Suggest(const std::string& type_name, std::size_t max_suggestions) const {
  return ClosestNames(type_name, TypeNames(), max_suggestions);
}

}  // namespace mb
