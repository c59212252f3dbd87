#pragma once
// How a diagram is run against a measurement (its "experiment": {"mode": …}). The names are the file format's, and
// this table is the one place they are written: the schema's enum, the reader and every JSON result come from it.
//   simulation      the measured inputs (a reference, a command) drive the model; its outputs (a position) are
//                   compared with the measured ones (output-error).
//   equation_error  the measured motion drives an inverse model; its output (a force) is compared with the measured
//                   force (IDIM-LS's setting; Gautier, Janot, Vandanjon 2013, IEEE TCST 21(2)).

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace mb {

enum class ExperimentMode { kSimulation, kEquationError };

/// The file format's names, in the enum's order.
inline constexpr std::array<std::string_view, 2> kExperimentModeNames{"simulation", "equation_error"};

/// "simulation" or "equation_error".
inline std::string_view Name(ExperimentMode mode) { return kExperimentModeNames[static_cast<std::size_t>(mode)]; }

/// The mode a name stands for. @throws std::invalid_argument naming the valid names.
inline ExperimentMode ExperimentModeNamed(std::string_view name) {
  for (std::size_t i = 0; i < kExperimentModeNames.size(); ++i) {
    if (name == kExperimentModeNames[i]) return static_cast<ExperimentMode>(i);
  }
  throw std::invalid_argument("experiment.mode '" + std::string(name) +
                              "' is not a mode: use \"simulation\" or \"equation_error\"");
}

/// JSON results write the mode by its name (nlohmann's ADL hook).
inline void to_json(nlohmann::json& j, ExperimentMode mode) { j = std::string(Name(mode)); }

}  // namespace mb
