#pragma once
// The `motionblocks` subcommands register themselves, as blocks (MB_REGISTER_BLOCK) and effects do: a new command is
// one file in tools/commands/ (CMake globs the folder into an OBJECT library, so every registration is linked in).
// main() adds the registered commands to the CLI11 application in their listing order.
//
// One file per subcommand (STYLE.md, after CLI11's examples and micromamba): an options struct, a Setup function
// that declares the options and binds the callback, and a Run function that only calls the library and prints. The
// options several subcommands share are declared in cli_options.h.

#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace mb {

/// Adds one subcommand (its options and callback) to `app`.
using CommandSetup = void (*)(CLI::App& app);

/// Where a command is listed in `motionblocks --help`, in this order.
enum class CommandGroup { kSimulate, kMeasurements, kLearnedCompensation, kHardware, kBatch, kInspect };

struct CommandRegistration {
  std::string_view name;  ///< the subcommand's name on the command line ("compare")
  CommandGroup group = CommandGroup::kInspect;
  CommandSetup setup = nullptr;
  /// The command simulates a diagram: it gets --max-steps and the progress options (cli_options.h).
  bool simulates = false;
};

/// Adds `command` to the registry; returns true (for the static initialiser). Two commands of one name are a
/// programming error: std::logic_error.
bool RegisterCommand(const CommandRegistration& command);

/// Every registered command, by group and then by name.
std::vector<CommandRegistration> RegisteredCommands();

/// Adds every registered command to `app`, each simulating one with --max-steps and the progress options.
void AddRegisteredCommands(CLI::App& app);

}  // namespace mb

/// Registers a subcommand at static-initialisation time; once per command file, at namespace scope outside mb:
/// MB_REGISTER_COMMAND(compare, {"compare", mb::CommandGroup::kMeasurements, &mb::SetupCompareCommand, true}).
#define MB_REGISTER_COMMAND(identifier, ...)                                          \
  namespace {                                                                         \
  [[maybe_unused]] const bool kCommandRegistered_##identifier =                       \
      ::mb::RegisterCommand(::mb::CommandRegistration __VA_ARGS__);                   \
  }
