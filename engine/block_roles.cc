#include "engine/block_roles.h"

#include <algorithm>

namespace mb {

BlockRoleRegistry& BlockRoleRegistry::Global() {
  static BlockRoleRegistry registry;
  return registry;
}

bool BlockRoleRegistry::AddLoopRoles(const std::string& type, const std::vector<std::string>& roles) {
  auto& list = loop_roles_[type];
  list.insert(list.end(), roles.begin(), roles.end());
  return true;
}

bool BlockRoleRegistry::AddIoChannel(const std::string& type, IoChannelTrait trait) {
  io_channels_[type] = std::move(trait);
  return true;
}

std::vector<std::string> BlockRoleRegistry::TypesWithLoopRole(const std::string& role) const {
  std::vector<std::string> types;
  for (const auto& [type, roles] : loop_roles_) {
    if (std::find(roles.begin(), roles.end(), role) != roles.end()) types.push_back(type);
  }
  return types;  // sorted: the map's order
}

const IoChannelTrait* BlockRoleRegistry::IoChannelOf(const std::string& type) const {
  const auto it = io_channels_.find(type);
  return it == io_channels_.end() ? nullptr : &it->second;
}

}  // namespace mb
