#include "engine/fixed_step_solver.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/cvode_solver.h"
#include "engine/numerical_error.h"
#include "engine/solver_type.h"

namespace mb {

FixedStepSolver::FixedStepSolver(OdeSystem* system, Method method, double step)
    : system_(system), method_(method), step_(step) {
  if (!(step > 0.0)) throw std::invalid_argument(fmt::format("fixed-step solver: step must be > 0 s, got {}", step));
  const auto n = static_cast<std::size_t>(system->num_states());
  for (auto* v : {&x_, &k1_, &k2_, &k3_, &k4_, &tmp_}) v->assign(n, 0.0);
  g_old_.assign(static_cast<std::size_t>(system->num_roots()), 0.0);
  g_new_ = g_old_;
}

void FixedStepSolver::Reset(double t, const double* x) {
  t_ = t;
  std::copy(x, x + x_.size(), x_.begin());
  if (!g_old_.empty()) {
    system_->Roots(t_, x_.data(), g_old_.data());
    ++stats_.root_evaluations;
  }
  ++stats_.reinitialisations;
}

void FixedStepSolver::Step(double t, double h) {
  const std::size_t n = x_.size();
  system_->Derivatives(t, x_.data(), k1_.data());
  if (method_ == Method::kEuler) {
    for (std::size_t i = 0; i < n; ++i) x_[i] += h * k1_[i];
    stats_.rhs_evaluations += 1;
    return;
  }
  for (std::size_t i = 0; i < n; ++i) tmp_[i] = x_[i] + 0.5 * h * k1_[i];
  system_->Derivatives(t + 0.5 * h, tmp_.data(), k2_.data());
  for (std::size_t i = 0; i < n; ++i) tmp_[i] = x_[i] + 0.5 * h * k2_[i];
  system_->Derivatives(t + 0.5 * h, tmp_.data(), k3_.data());
  for (std::size_t i = 0; i < n; ++i) tmp_[i] = x_[i] + h * k3_[i];
  system_->Derivatives(t + h, tmp_.data(), k4_.data());
  for (std::size_t i = 0; i < n; ++i) x_[i] += h / 6.0 * (k1_[i] + 2.0 * k2_[i] + 2.0 * k3_[i] + k4_[i]);
  stats_.rhs_evaluations += 4;
}

double FixedStepSolver::Integrate(double t_stop, double* x, bool* root_found) {
  *root_found = false;
  // Land exactly on t_stop: n equal steps no longer than step_ (so sample hits are hit exactly).
  const double span = t_stop - t_;
  if (span > 0.0) {
    const auto n = static_cast<long>(std::max(1.0, std::ceil(span / step_ - 1e-9)));
    const double h = span / static_cast<double>(n);
    const double t0 = t_;
    for (long k = 1; k <= n; ++k) {
      Step(t_, h);
      t_ = k == n ? t_stop : t0 + static_cast<double>(k) * h;
      ++stats_.steps;
      CheckFinite();
      if (!g_old_.empty()) {
        system_->Roots(t_, x_.data(), g_new_.data());
        ++stats_.root_evaluations;
        last_root_ = -1;
        for (std::size_t i = 0; i < g_new_.size(); ++i) {
          if (last_root_ < 0 && (g_old_[i] > 0.0) != (g_new_[i] > 0.0)) last_root_ = static_cast<int>(i);
        }
        const bool crossed = last_root_ >= 0;
        g_old_ = g_new_;
        if (crossed) {
          *root_found = true;
          ++stats_.roots_found;
          break;
        }
      }
    }
  }
  std::copy(x_.begin(), x_.end(), x);
  return t_;
}

void FixedStepSolver::CheckFinite() const {
  for (const double v : x_) {
    if (std::isfinite(v)) continue;
    throw NumericalError(fmt::format("{} solver: {} after the step to t = {:.9g} s (step {} s). The model diverged "
                                     "or a block computed an invalid value: check that block's parameters and "
                                     "inputs, or try a smaller solver.step or the cvode solver",
                                     name(), system_->DescribeNonFinite(x_.data()), t_, step_));
  }
}

std::unique_ptr<ContinuousSolver> MakeSolver(const SolverSpec& spec, OdeSystem* system) {
  const std::optional<SolverType> type = SolverTypeNamed(spec.type);
  if (!type) {
    throw std::invalid_argument(fmt::format("unknown solver '{}': use {}", spec.type, fmt::join(kSolverTypeNames, ", ")));
  }
  switch (*type) {
    case SolverType::kEuler:
      return std::make_unique<FixedStepSolver>(system, FixedStepSolver::Method::kEuler, spec.step);
    case SolverType::kRk4:
      return std::make_unique<FixedStepSolver>(system, FixedStepSolver::Method::kRk4, spec.step);
    case SolverType::kCvode:
      return std::make_unique<CvodeSolver>(system, spec);
  }
  throw std::logic_error("MakeSolver: a solver type without a solver");
}

}  // namespace mb
