#include "models/gpr/gpr_log.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace mb {

Table ReadGprTable(const std::string& path, const std::vector<std::string>& required_columns) {
  TableReadOptions read;
  read.required_columns = required_columns;
  read.kind = "table";
  read.drop_unnamed_index = true;
  return ReadTable(path, read);
}

std::pair<std::string, std::string> GprInputColumns(const GprModel& model, const std::string& position,
                                                    const std::string& velocity) {
  const GprProvenance& p = model.data().provenance;
  const auto pick = [](const std::string& given, const std::string& trained, const char* fallback) {
    return !given.empty() ? given : !trained.empty() ? trained : std::string(fallback);
  };
  return {pick(position, p.position_column, "position_m"), pick(velocity, p.velocity_column, "velocity_m_s")};
}

namespace {

// The training columns a GP can scale its priors to (DefaultGprPriors): positions that move, a disturbance that
// varies, spans that are finite numbers. @throws std::invalid_argument naming the file, the column and the fix, not
// the prior's function (issue 30: "DefaultGprPriors: the trained position range … got 0.000000").
void CheckGprTrainingSpread(const std::string& source, const GprTrainingSelection& selection,
                            const GprTrainingData& data) {
  const auto n = data.x.size();
  const struct {
    const Eigen::VectorXd& values;
    const std::string& column;
    const char* option;
    const char* unit;
    bool may_be_constant;  // one scan velocity is widened (TrainedVelocityRange)
    bool motion;           // a position or velocity: bounded by kMaxGprMotionMagnitude
  } columns[] = {{data.x, selection.position_column, "--position-column", " m", false, true},
                 {data.xdot, selection.velocity_column, "--velocity-column", " m/s", true, true},
                 {data.d, selection.disturbance_column, "--disturbance-column", "", false, false}};
  // No stage travels a million metres, nor at a million m/s: such values are a unit or column mistake (1e300 m was
  // fitted without a word; tests/hostile), and the periodic features lose every digit of their phase there.
  constexpr double kMaxGprMotionMagnitude = 1e6;
  for (const auto& c : columns) {
    const double low = c.values.minCoeff(), high = c.values.maxCoeff();
    if (!std::isfinite(high - low)) {
      throw std::invalid_argument(fmt::format(
          "{}: column '{}' spans [{:g}, {:g}]{} over the {} training rows, a range no GP can be scaled to: check the "
          "column's values and unit (SI: metres, seconds), or name another column with {}",
          source, c.column, low, high, c.unit, n, c.option));
    }
    if (c.motion && std::max(std::abs(low), std::abs(high)) > kMaxGprMotionMagnitude) {
      throw std::invalid_argument(fmt::format(
          "{}: column '{}' reaches {:g}{} over the {} training rows, beyond the {:g}{} any stage moves: check the "
          "column's values and unit (SI: metres, seconds), or name another column with {}",
          source, c.column, std::abs(low) > std::abs(high) ? low : high, c.unit, n, kMaxGprMotionMagnitude, c.unit,
          c.option));
    }
    if (!(high > low) && !c.may_be_constant) {
      throw std::invalid_argument(fmt::format(
          "{}: column '{}' is constant ({:g}{}) over the {} training rows: a GP learns nothing from it; give a record "
          "in which it varies (a scan over the travel), or name another column with {}",
          source, c.column, low, c.unit, n, c.option));
    }
  }
}

}  // namespace

GprTrainingData SelectGprTrainingData(const MeasurementLog& log, const GprTrainingSelection& selection) {
  if (selection.disturbance_column.empty()) {
    throw std::invalid_argument(log.source() + ": no disturbance column given: name the column of the "
                                "disturbance estimate to learn (e.g. the DOB output)");
  }
  if (selection.downsample < 1) {
    throw std::invalid_argument(fmt::format("downsample must be >= 1 (keep every n-th sample), got {}",
                                            selection.downsample));
  }
  if (selection.window) {
    const GprRange w = *selection.window;
    if (!std::isfinite(w.min) || !std::isfinite(w.max) || !(w.min < w.max)) {
      throw std::invalid_argument(fmt::format("position window [{:g}, {:g}] m is empty or not finite: give "
                                              "xmin < xmax",
                                              w.min, w.max));
    }
  }
  const Eigen::VectorXd& x = log.column(selection.position_column);
  const Eigen::VectorXd& xdot = log.column(selection.velocity_column);
  const Eigen::VectorXd& d = log.column(selection.disturbance_column);

  std::vector<Eigen::Index> rows;
  rows.reserve(static_cast<std::size_t>(log.rows()));
  Eigen::Index in_window = 0;
  for (Eigen::Index i = 0; i < log.rows(); ++i) {
    if (selection.window && !(x(i) >= selection.window->min && x(i) <= selection.window->max)) continue;
    if (in_window++ % selection.downsample == 0) rows.push_back(i);
  }
  if (rows.size() < static_cast<std::size_t>(kMinGprSamples)) {
    const std::string window =
        selection.window ? fmt::format(" in the position window [{:g}, {:g}] m", selection.window->min,
                                       selection.window->max)
                         : "";
    throw std::invalid_argument(fmt::format(
        "{}: {} training sample(s){} (column {} spans [{:g}, {:g}] m over {} rows); a GP fit needs at least {} "
        "(it estimates its hyperparameters from the data): give a longer log, widen the window or lower "
        "--downsample",
        log.source(), rows.size(), window, selection.position_column, log.rows() > 0 ? x.minCoeff() : 0.0,
        log.rows() > 0 ? x.maxCoeff() : 0.0, log.rows(), kMinGprSamples));
  }

  const auto n = static_cast<Eigen::Index>(rows.size());
  GprTrainingData data{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n), {}};
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index i = rows[static_cast<std::size_t>(k)];
    data.x(k) = x(i);
    data.xdot(k) = xdot(i);
    data.d(k) = d(i);
  }
  CheckGprTrainingSpread(log.source(), selection, data);
  std::string description =
      fmt::format("{} (position: {}, velocity: {}, disturbance: {}", log.source(), selection.position_column,
                  selection.velocity_column, selection.disturbance_column);
  if (selection.window) {
    description += fmt::format(", window [{:g}, {:g}] m", selection.window->min, selection.window->max);
  }
  if (selection.downsample > 1) description += fmt::format(", downsampled by {}", selection.downsample);
  description += fmt::format("; N = {} of {} rows)", n, log.rows());
  data.description = std::move(description);
  return data;
}

GprModel FitGprToLog(const MeasurementLog& log, const GprTrainingSelection& selection, GprFitOptions options) {
  const GprTrainingData data = SelectGprTrainingData(log, selection);
  options.source = data.description;
  options.accept_one_velocity = true;
  GprModelData model = FitGpr(data.x, data.xdot, data.d, options).data();
  model.provenance.position_column = selection.position_column;
  model.provenance.velocity_column = selection.velocity_column;
  return GprModel(std::move(model));
}

bool GprExtrapolates(const GprModel& model, double x, double xdot) noexcept {
  const GprRange xr = model.x_range(), vr = model.xdot_range();
  // Written so that NaN (every comparison false) counts as outside.
  return !(x >= xr.min && x <= xr.max && xdot >= vr.min && xdot <= vr.max);
}

MeasurementLog PredictGprOnLog(const GprModel& model, const MeasurementLog& log,
                               const std::string& position_column, const std::string& velocity_column) {
  for (const char* name : {"mean", "std", kGprExtrapolatedColumn}) {
    if (log.has_column(name)) {
      throw std::invalid_argument(log.source() + ": already has a column \"" + name +
                                  "\", which the prediction would write: rename it in the input");
    }
  }
  const Eigen::VectorXd& x = log.column(position_column);
  const Eigen::VectorXd& xdot = log.column(velocity_column);
  Eigen::VectorXd mean(log.rows()), sd(log.rows()), extrapolated(log.rows());
  for (Eigen::Index i = 0; i < log.rows(); ++i) {
    mean(i) = model.PredictPosteriorMean(x(i), xdot(i));
    model.Predict(x(i), xdot(i), nullptr, &sd(i));
    extrapolated(i) = GprExtrapolates(model, x(i), xdot(i)) ? 1.0 : 0.0;
  }
  std::vector<Eigen::VectorXd> columns;
  columns.reserve(log.names().size() + 3);
  for (const std::string& name : log.names()) columns.push_back(log.column(name));
  std::vector<std::string> names = log.names();
  names.emplace_back("mean");
  names.emplace_back("std");
  names.emplace_back(kGprExtrapolatedColumn);
  columns.push_back(std::move(mean));
  columns.push_back(std::move(sd));
  columns.push_back(std::move(extrapolated));
  return MeasurementLog(std::move(names), std::move(columns), log.source());
}

}  // namespace mb
