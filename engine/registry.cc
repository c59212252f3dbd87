#include "engine/registry.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/closest_names.h"
#include "engine/json_schema.h"

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

const BlockType& BlockRegistry::DifferenceOfTwo() const {
  for (const auto& [name, type] : types_) {
    if (type.difference_of_two) return type;
  }
  throw std::logic_error(
      "no registered block type subtracts two signals (difference_of_two): link mb_blocks into the program");
}

std::vector<std::string> BlockRegistry::Suggest(const std::string& type_name, std::size_t max_suggestions) const {
  return ClosestNames(type_name, TypeNames(), max_suggestions);
}

}  // namespace mb
