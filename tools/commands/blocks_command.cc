// motionblocks blocks [TYPE]: the block reference (types, parameters with units and defaults).

#include <iostream>

#include <fmt/format.h>

#include "engine/registry.h"
#include "tools/commands/commands.h"

namespace mb {

namespace {
void RunBlocks(const std::string& type) {
  const auto& registry = BlockRegistry::Global();
  for (const auto& name : registry.TypeNames()) {
    if (!type.empty() && name != type) continue;
    const BlockType& bt = *registry.Find(name);
    std::cout << fmt::format("{}\n    {}\n", name, bt.description);
    for (const auto& p : bt.parameters) {
      std::cout << fmt::format("    - {} ({}{}){}: {}\n", p.name, ToString(p.type), p.unit.empty() ? "" : ", " + p.unit,
                               p.default_value ? " = " + p.default_value->dump() : " [required]", p.description);
    }
  }
}
}  // namespace

void SetupBlocksCommand(CLI::App& app) {
  auto type = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand("blocks", "List the block types with their parameters");
  cmd->add_option("type", *type, "show one type only");
  cmd->callback([type] { RunBlocks(*type); });
}

}  // namespace mb
