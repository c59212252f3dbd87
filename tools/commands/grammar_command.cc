// motionblocks grammar: the diagnosis' grammar of candidate effects in Markdown — the multipliers (what a missing force
// is proportional to), the modulators (what it varies with) and every pair by the name the diagnosis gives it
// (models/diagnosis/factors.h; docs/diagnosis.md, "The grammar", holds the same text).

#include <iostream>

#include "models/diagnosis/factors.h"
#include "tools/commands/command_registry.h"

namespace mb {

namespace {

void SetupGrammarCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("grammar", "Print the diagnosis' grammar: multipliers, modulators and every pair");
  cmd->callback([] { std::cout << GrammarMarkdown(); });
}

}  // namespace

MB_REGISTER_COMMAND(grammar, {"grammar", CommandGroup::kInspect, &SetupGrammarCommand, false})

}  // namespace mb
