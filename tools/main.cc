// motionblocks: block-diagram simulation for precision motion control. One top-level catch: every error
// reaches the user as one clear message and a non-zero exit code.

#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/file_access.h"
#include "tools/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"motionblocks — block-diagram simulation, model-vs-measurement diagnosis and learned disturbance "
               "compensation for precision motion control"};
  app.require_subcommand(1);
  app.fallthrough();  // global options may follow the subcommand
  app.add_option_function<std::vector<std::string>>(
         "--allow-path",
         [](const std::vector<std::string>& folders) {
           for (const auto& folder : folders) mb::AllowDiagramFilesUnder(folder);
         },
         "A folder outside the diagram's own whose files the diagram's file parameters (from_file.file, gpr.model, "
         "subsystem diagram) may read; repeat for several")
      ->type_name("DIR")
      ->allow_extra_args(false);
  mb::SetupRunCommand(app);
  mb::SetupCompareCommand(app);
  mb::SetupFitCommand(app);
  mb::SetupImproveCommand(app);
  mb::SetupBlocksCommand(app);
  mb::SetupFitGprCommand(app);
  mb::SetupPredictGprCommand(app);
  mb::SetupHilCommand(app);
  mb::SetupVirtualStageCommand(app);
  mb::SetupStabilityCommand(app);
  mb::SetupSweepCommand(app);
  mb::SetupReproduceCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "motionblocks: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
