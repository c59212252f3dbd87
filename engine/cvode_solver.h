#pragma once
// CVODE (SUNDIALS ≥ 6) as a ContinuousSolver: BDF (stiff) or Adams–Moulton, dense Newton linear solver,
// rootfinding on the diagram's zero-crossing functions, a stop time at every major step so that it never steps
// over a sample hit, and CVodeReInit after discrete events. RAII for every SUNDIALS object (Cantera's wrapper is
// the model). Source: Hindmarsh et al., "SUNDIALS: Suite of nonlinear and differential/algebraic equation
// solvers", ACM TOMS 31 (2005); the CVODE user guide v6.4.

#include <memory>
#include <string>

#include "engine/solver.h"
#include "engine/solver_type.h"

namespace mb {

class CvodeSolver final : public ContinuousSolver {
 public:
  /// A right-hand side that returns NaN/Inf is a recoverable error (CVODE retries with a smaller step); if CVODE
  /// still fails, NumericalError names the non-finite value. Uses spec.method ("bdf"/"adams"), rtol, atol, max_step (0 = unlimited). @throws std::runtime_error if
  /// SUNDIALS cannot be set up.
  CvodeSolver(OdeSystem* system, const SolverSpec& spec);
  ~CvodeSolver() override;

  void Reset(double t, const double* x) override;
  double Integrate(double t_stop, double* x, bool* root_found) override;
  const SolverStats& stats() const override;
  std::string name() const override { return std::string(Name(SolverType::kCvode)); }
  int last_root() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mb
