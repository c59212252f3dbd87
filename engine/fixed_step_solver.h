#pragma once
// Fixed-step explicit solvers: forward Euler (order 1) and classical Runge–Kutta (order 4). Source: Hairer,
// Nørsett, Wanner, "Solving Ordinary Differential Equations I", §II.1.

#include <string>
#include <vector>

#include "engine/solver.h"
#include "engine/solver_type.h"

namespace mb {

class FixedStepSolver final : public ContinuousSolver {
 public:
  enum class Method { kEuler, kRk4 };
  /// step [s] > 0: the largest step; the last step before a stop time is shortened to land on it exactly.
  FixedStepSolver(OdeSystem* system, Method method, double step);

  void Reset(double t, const double* x) override;
  double Integrate(double t_stop, double* x, bool* root_found) override;
  const SolverStats& stats() const override { return stats_; }
  std::string name() const override {
    return std::string(Name(method_ == Method::kEuler ? SolverType::kEuler : SolverType::kRk4));
  }
  int last_root() const override { return last_root_; }

 private:
  void Step(double t, double h);
  /// @throws NumericalError naming the first non-finite state.
  void CheckFinite() const;
  OdeSystem* system_;
  Method method_;
  double step_;
  double t_ = 0.0;
  int last_root_ = -1;
  std::vector<double> x_, k1_, k2_, k3_, k4_, tmp_, g_old_, g_new_;
  SolverStats stats_;
};

}  // namespace mb
