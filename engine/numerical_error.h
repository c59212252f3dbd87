#pragma once
// NumericalError: a simulation whose numbers failed, as opposed to bad input (std::invalid_argument,
// DiagramError) or another failure. The command line exits with code 3 on it (README "Exit codes").

#include <stdexcept>

namespace mb {

/// Thrown when a run cannot go on numerically: a block output or a state became NaN or ±Inf (the message names
/// the block, the port or state and the time, and says where to look), an integrator failed (CVODE's flag), or
/// events repeat without time advancing (a Zeno loop; the message names the block whose zero crossing fires).
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mb
