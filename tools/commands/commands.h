#pragma once
// The `motionblocks` subcommands. One file per subcommand (STYLE.md): an options struct, a Setup…(CLI::App&)
// that declares the options and binds the callback, and a Run…(const Options&) that only calls the library
// and prints. The options several subcommands share are declared in cli_options.h.

#include <CLI/CLI.hpp>

namespace mb {

void SetupRunCommand(CLI::App& app);
void SetupCompareCommand(CLI::App& app);
void SetupImproveCommand(CLI::App& app);
void SetupFitCommand(CLI::App& app);
void SetupBlocksCommand(CLI::App& app);
void SetupFitGprCommand(CLI::App& app);
void SetupPredictGprCommand(CLI::App& app);
void SetupHilCommand(CLI::App& app);
void SetupVirtualStageCommand(CLI::App& app);
void SetupStabilityCommand(CLI::App& app);
void SetupSweepCommand(CLI::App& app);
void SetupSweepMergeCommand(CLI::App& app);
void SetupReproduceCommand(CLI::App& app);
void SetupSchemaCommand(CLI::App& app);
void SetupDrawCommand(CLI::App& app);

}  // namespace mb
