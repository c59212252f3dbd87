#pragma once
// Continuous-time solvers for the states of a diagram: fixed-step explicit Euler and classical RK4, and CVODE
// (SUNDIALS; BDF or Adams) with rootfinding. The simulator calls them between major time steps (sample hits and
// log times), and re-initialises them after every discrete event.

#include <memory>
#include <string>

#include "engine/diagram.h"

namespace mb {

/// The continuous part of a diagram seen by a solver: ẋ = f(t, x) and zero-crossing functions g(t, x).
class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual int num_states() const = 0;
  virtual int num_roots() const = 0;
  /// dx[0..n) = f(t, x). May throw (the CVODE wrapper converts that to a recoverable error).
  virtual void Derivatives(double t, const double* x, double* dx) = 0;
  /// g[0..num_roots) = g(t, x).
  virtual void Roots(double t, const double* x, double* g) = 0;
  /// Where the first NaN/Inf is, for an error message: the first non-finite block output of the latest evaluation
  /// (in execution order), else the first non-finite entry of the state x (named by its block), else "".
  virtual std::string DescribeNonFinite(const double* x) const = 0;
};

/// Counters that users look at when a run is slow or stiff.
struct SolverStats {
  long steps = 0;
  long rhs_evaluations = 0;
  long root_evaluations = 0;
  long reinitialisations = 0;
  long roots_found = 0;
};

class ContinuousSolver {
 public:
  virtual ~ContinuousSolver() = default;
  /// (Re)starts integration at time t from state x (after initialisation or a discrete event).
  virtual void Reset(double t, const double* x) = 0;
  /// Integrates from the current time towards t_stop (never past it). Writes the state reached into x and
  /// returns the time reached: t_stop, or the time of the first zero crossing, in which case *root_found is
  /// true. Fixed-step solvers locate a crossing to the end of the step in which g changed sign; CVODE locates
  /// it to its root tolerance. @throws NumericalError (engine/numerical_error.h) when a state becomes NaN/Inf
  /// (naming it through OdeSystem::DescribeNonFinite) or CVODE fails (with its flag name).
  virtual double Integrate(double t_stop, double* x, bool* root_found) = 0;
  /// Index of a root function that crossed at the last Integrate that returned *root_found, else -1.
  virtual int last_root() const = 0;
  virtual const SolverStats& stats() const = 0;
  virtual std::string name() const = 0;
};

/// Creates the solver named in the diagram's `solver` section for `system` (which must outlive the solver).
/// @throws std::invalid_argument for an unknown type.
std::unique_ptr<ContinuousSolver> MakeSolver(const SolverSpec& spec, OdeSystem* system);

}  // namespace mb
