// motionblocks: block-diagram simulation for precision motion control. One top-level catch: every error
// reaches the user as one clear message and a non-zero exit code.

#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "tools/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"motionblocks — block-diagram simulation, model-vs-measurement diagnosis and learned disturbance "
               "compensation for precision motion control"};
  app.require_subcommand(1);
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
  mb::SetupSchemaCommand(app);
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
