// --max-steps N on every command that simulates: raises (or lowers) the run-length limit that Simulator checks
// before a run (engine/simulator.h SimulationLimits), for every simulation the command starts.

#include <fmt/format.h>

#include "engine/simulator.h"
#include "tools/commands.h"

namespace mb {

void AddMaxStepsOption(CLI::App* command) {
  command
      ->add_option_function<double>(
          "--max-steps",
          [](const double& n) {
            SimulationLimits limits = DefaultSimulationLimits();
            limits.max_steps = n;
            SetDefaultSimulationLimits(limits);
          },
          fmt::format("refuse a simulation estimated to take more steps, or to log more values, than N (default "
                      "{:.0e}; protects against a stopTime or step typo that would run for hours or exhaust memory)",
                      SimulationLimits{}.max_steps))
      ->type_name("N")
      ->check(CLI::PositiveNumber);
}

}  // namespace mb
