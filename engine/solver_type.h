#pragma once
// The solvers a diagram's "solver" section names and CVODE's methods. The names are the file format's and this table
// is the one place they are written: the schema's enums, the reader's check and the solver factory come from it.

#include <array>
#include <optional>
#include <string_view>

namespace mb {

enum class SolverType {
  kEuler,  ///< explicit Euler, fixed step (engine/fixed_step_solver.h)
  kRk4,    ///< classical Runge–Kutta, fixed step (the default)
  kCvode,  ///< SUNDIALS CVODE, variable step (engine/cvode_solver.h)
};

/// The file format's names, in the enum's order.
inline constexpr std::array<std::string_view, 3> kSolverTypeNames{"euler", "rk4", "cvode"};
/// CVODE's linear multistep methods: "bdf" (stiff, the default) and "adams".
inline constexpr std::array<std::string_view, 2> kCvodeMethodNames{"bdf", "adams"};

inline std::string_view Name(SolverType type) { return kSolverTypeNames[static_cast<std::size_t>(type)]; }

/// The solver a name stands for; nullopt for any other text.
inline std::optional<SolverType> SolverTypeNamed(std::string_view name) {
  for (std::size_t i = 0; i < kSolverTypeNames.size(); ++i) {
    if (name == kSolverTypeNames[i]) return static_cast<SolverType>(i);
  }
  return std::nullopt;
}

}  // namespace mb
