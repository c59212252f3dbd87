// motionblocks blocks [TYPE]: the block reference (engine/registry.h BlockReference): each type's ports (direction,
// name, unit, direct feedthrough), parameters with units and defaults, sampleTime rule and a minimal element.

#include <iostream>

#include "engine/registry.h"
#include "tools/commands/command_registry.h"

namespace mb {

namespace {
void RunBlocks(const std::string& type) {
  const auto& registry = BlockRegistry::Global();
  if (!type.empty()) {
    std::cout << BlockReference(registry.Get(type));  // an unknown name: std::invalid_argument, exit 2
    return;
  }
  for (const auto& name : registry.TypeNames()) std::cout << BlockReference(*registry.Find(name)) << "\n";
}

void SetupBlocksCommand(CLI::App& app) {
  auto type = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand("blocks", "List the block types with their ports, parameters and an example element");
  cmd->add_option("type", *type, "show one type only");
  cmd->callback([type] { RunBlocks(*type); });
}

}  // namespace

MB_REGISTER_COMMAND(blocks, {"blocks", CommandGroup::kInspect, &SetupBlocksCommand, false})

}  // namespace mb
