// The smoothed inverse-model disturbance estimate (disturbance_target.h).

#include "models/gpr/disturbance_target.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/signal_processing.h"

namespace mb {

namespace {

void CheckSmoothedDisturbanceInput(const Eigen::Ref<const Eigen::VectorXd>& time,
                                   const Eigen::Ref<const Eigen::VectorXd>& position,
                                   const Eigen::Ref<const Eigen::VectorXd>& force,
                                   const SmoothedDisturbanceOptions& o) {
  if (time.size() != position.size() || time.size() != force.size()) {
    throw std::invalid_argument(fmt::format("smoothed disturbance estimate: time, position and force must have the "
                                            "same length, got {}, {} and {} samples",
                                            time.size(), position.size(), force.size()));
  }
  if (time.size() < 3) {
    throw std::invalid_argument(
        fmt::format("smoothed disturbance estimate: needs at least 3 samples, got {}", time.size()));
  }
  for (Eigen::Index i = 1; i < time.size(); ++i) {
    if (!(time[i] > time[i - 1])) {
      throw std::invalid_argument(fmt::format("smoothed disturbance estimate: time must increase, but t[{}] = {:g} s "
                                              "follows t[{}] = {:g} s (estimate each scan separately)",
                                              i, time[i], i - 1, time[i - 1]));
    }
  }
  if (!(o.nominal_mass > 0.0) || !std::isfinite(o.nominal_mass)) {
    throw std::invalid_argument(fmt::format(
        "smoothed disturbance estimate: nominal mass must be positive and finite [kg], got {:g}", o.nominal_mass));
  }
  if (!(o.nominal_damping >= 0.0) || !std::isfinite(o.nominal_damping)) {
    throw std::invalid_argument(fmt::format(
        "smoothed disturbance estimate: nominal damping must be >= 0 and finite [N*s/m], got {:g}",
        o.nominal_damping));
  }
}

// The force that matches the central second difference of the position at each sample: the same symmetric
// smoothing kernel the two central differences apply to the acceleration, on the held (or sampled) force.
Eigen::VectorXd ForceMatchingTheDifferences(const Eigen::Ref<const Eigen::VectorXd>& u, bool held) {
  const Eigen::Index n = u.size();
  const auto at = [&](Eigen::Index i) { return u[std::clamp<Eigen::Index>(i, 0, n - 1)]; };
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    // Held: a_j acts on [t_j, t_j+1), and (x_{k+2} − 2x_k + x_{k−2})/(4Ts²) = (a_{k−2} + 3a_{k−1} + 3a_k + a_{k+1})/8.
    out[k] = held ? (at(k - 2) + 3.0 * at(k - 1) + 3.0 * at(k) + at(k + 1)) / 8.0
                  : (at(k - 1) + 2.0 * at(k) + at(k + 1)) / 4.0;
  }
  return out;
}

}  // namespace

Eigen::VectorXd SmoothedDisturbanceEstimate(const Eigen::Ref<const Eigen::VectorXd>& time,
                                            const Eigen::Ref<const Eigen::VectorXd>& position,
                                            const Eigen::Ref<const Eigen::VectorXd>& force,
                                            const SmoothedDisturbanceOptions& options) {
  CheckSmoothedDisturbanceInput(time, position, force, options);
  const MotionDerivatives motion = DeriveMotion(time, position, options.cutoff_hz);
  const Eigen::VectorXd u = ZeroPhaseLowPass(ForceMatchingTheDifferences(force, options.force_held),
                                             MedianTimeStep(time), options.cutoff_hz);
  return options.nominal_mass * motion.acceleration + options.nominal_damping * motion.velocity - u;
}

void AddSmoothedDisturbanceColumn(Table& table, const std::string& time_column, const std::string& position_column,
                                  const std::string& force_column, const SmoothedDisturbanceOptions& options,
                                  const std::string& output_column) {
  if (table.has_column(output_column)) {
    throw std::invalid_argument(fmt::format("{}: already has a column '{}': rename it or choose another name",
                                            table.source(), output_column));
  }
  const Eigen::VectorXd& t = table.column(time_column);
  const Eigen::VectorXd& x = table.column(position_column);
  const Eigen::VectorXd& u = table.column(force_column);
  const Eigen::Index n = table.rows();
  std::vector<std::pair<Eigen::Index, Eigen::Index>> segments;
  if (n >= 2) {
    std::vector<double> steps;
    for (Eigen::Index i = 1; i < n; ++i) {
      if (t[i] > t[i - 1]) steps.push_back(t[i] - t[i - 1]);
    }
    std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
    const double median = steps.empty() ? 0.0 : steps[steps.size() / 2];
    Eigen::Index begin = 0;
    for (Eigen::Index i = 1; i < n; ++i) {
      if (!(t[i] > t[i - 1]) || t[i] - t[i - 1] > 1.5 * median) {
        segments.emplace_back(begin, i);
        begin = i;
      }
    }
    segments.emplace_back(begin, n);
  } else {
    segments.emplace_back(0, n);
  }
  Eigen::VectorXd d(n);
  for (const auto& [begin, end] : segments) {
    if (end - begin < 3) {
      throw std::invalid_argument(fmt::format("{}: the scan at rows {}..{} ({}) has fewer than 3 samples: the "
                                              "smoothed estimate needs a time series per scan",
                                              table.source(), begin + 1, end, time_column));
    }
    d.segment(begin, end - begin) = SmoothedDisturbanceEstimate(
        t.segment(begin, end - begin), x.segment(begin, end - begin), u.segment(begin, end - begin), options);
  }
  table.AddColumn(output_column, std::move(d));
}

}  // namespace mb
