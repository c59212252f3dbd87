#include "tools/commands/command_registry.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "tools/commands/cli_options.h"

namespace mb {

namespace {

// Function-local, so that registrations from other translation units' static initialisers find it constructed.
std::vector<CommandRegistration>& Registry() {
  static std::vector<CommandRegistration> commands;
  return commands;
}

const char* GroupTitle(CommandGroup group) {
  switch (group) {
    case CommandGroup::kSimulate: return "Simulate";
    case CommandGroup::kMeasurements: return "Compare with measurements";
    case CommandGroup::kLearnedCompensation: return "Learned compensation (TISO-GPR)";
    case CommandGroup::kHardware: return "Hardware in the loop";
    case CommandGroup::kBatch: return "Batch";
    case CommandGroup::kInspect: return "Inspect";
  }
  return "Commands";
}

}  // namespace

bool RegisterCommand(const CommandRegistration& command) {
  auto& commands = Registry();
  const bool taken = std::any_of(commands.begin(), commands.end(),
                                 [&](const CommandRegistration& c) { return c.name == command.name; });
  if (taken || command.setup == nullptr || command.name.empty()) {
    throw std::logic_error("RegisterCommand: command '" + std::string(command.name) +
                           "' is registered twice or has no name or setup");
  }
  commands.push_back(command);
  return true;
}

std::vector<CommandRegistration> RegisteredCommands() {
  std::vector<CommandRegistration> commands = Registry();
  std::sort(commands.begin(), commands.end(), [](const CommandRegistration& a, const CommandRegistration& b) {
    return a.group != b.group ? a.group < b.group : a.name < b.name;
  });
  return commands;
}

void AddRegisteredCommands(CLI::App& app) {
  for (const CommandRegistration& command : RegisteredCommands()) {
    command.setup(app);
    CLI::App* added = app.get_subcommand(std::string(command.name));
    added->group(GroupTitle(command.group));
    if (!command.simulates) continue;
    AddMaxStepsOption(added);
    AddProgressOptions(added);
  }
}

}  // namespace mb
