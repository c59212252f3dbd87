#include "tools/report/residual_figures.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/periodogram.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {

namespace fs = std::filesystem;

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

void AddResidualFigures(HtmlReport* report, const fs::path& out, const MeasurementLog& log,
                        const ComparedOutput& before, const Eigen::VectorXd& residual_after,
                        const DiagnosisResult* diagnosis, const std::string& position_column) {
  const auto t = ToStd(log.time());
  Figure overlay{"model_vs_measurement.png", fmt::format("{}: measured vs model", before.connector), "time [s]",
                 fmt::format("{} [{}]", before.connector, before.unit), {}};
  overlay.series.push_back({t, ToStd(before.measured), "measured (" + before.column + ")", "lines"});
  overlay.series.push_back({t, ToStd(before.model), "model", "lines"});
  overlay.x_link = "time";
  report->AddFigure(overlay, out);

  Figure rt{"residual_vs_time.png", "Residual against time (after the fit)", "time [s]",
            fmt::format("measured − model [{}]", before.unit), {}};
  rt.series.push_back({t, ToStd(residual_after), "residual", "lines"});
  rt.x_link = "time";
  report->AddFigure(rt, out);
  if (log.has_column(position_column)) {
    Figure rx{"residual_vs_position.png", "Residual against position", "position [m]",
              fmt::format("residual [{}]", before.unit), {}};
    rx.series.push_back({ToStd(log.column(position_column)), ToStd(residual_after), "residual", "dots"});
    report->AddFigure(rx, out);
  }
  const std::string velocity_column = DerivedVelocityColumn(position_column);
  const std::string acceleration_column = DerivedAccelerationColumn(position_column);
  if (log.has_column(velocity_column)) {
    const BinnedResidual b = BinResidual(log.column(velocity_column), residual_after, 40);
    std::vector<double> xs, ys;
    for (Eigen::Index i = 0; i < b.centers.size(); ++i) {
      if (b.count(i) > 0) {
        xs.push_back(b.centers(i));
        ys.push_back(b.mean(i));
      }
    }
    Figure rv{"residual_vs_velocity.png", "Residual against velocity (binned mean: the friction shape)",
              "velocity [m/s]", fmt::format("residual [{}]", before.unit), {}};
    rv.series.push_back({ToStd(log.column(velocity_column)), ToStd(residual_after), "samples", "dots"});
    rv.series.push_back({xs, ys, "bin mean", "lines"});
    report->AddFigure(rv, out);
  }
  if (log.has_column(acceleration_column)) {
    Figure ra{"residual_vs_acceleration.png", "Residual against acceleration (a slope: mass mismatch)",
              "acceleration [m/s²]", fmt::format("residual [{}]", before.unit), {}};
    ra.series.push_back({ToStd(log.column(acceleration_column)), ToStd(residual_after), "samples", "dots"});
    report->AddFigure(ra, out);
  }
  if (diagnosis && !diagnosis->position_peaks.empty()) {
    // Re-plot the periodogram from the peaks list is too sparse; compute the full one here for the figure.
    const Periodogram pg = PositionPeriodogram(log.column(position_column), residual_after);
    Figure fp{"position_periodogram.png", "Position-domain periodogram of the residual (share of variance explained)",
              "period [m]", "power", {}};
    fp.log_x = true;
    fp.series.push_back({ToStd(pg.periods), ToStd(pg.power), "floating-mean Lomb–Scargle", "lines"});
    for (const auto& e : diagnosis->effects) {  // the periods the ranking chose, where the text names them
      const auto period = e.parameters.find("period");
      if (period != e.parameters.end()) {
        const std::string unit = PositionUnitToken(position_column);
        fp.x_marks.emplace_back(period->second,
                                unit == "m" ? fmt::format("{} {:.4g} mm", e.effect, 1e3 * period->second)
                                            : fmt::format("{} {:.4g} {}", e.effect, period->second, unit));
      }
    }
    report->AddFigure(fp, out);
  }
}

namespace {

// One axis an effect's evidence can be drawn against.
struct EvidenceAxis {
  std::string label;
  Eigen::VectorXd values;
  bool folded = false;
};

// The share of the variance of `y` that its means over 64 uniform bins of `x` hold (1: y is a function of x);
// −1 for a constant or absent axis.
double BinnedShare(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  if (x.size() != y.size() || x.size() < 2 || !(x.maxCoeff() > x.minCoeff())) return -1.0;
  const BinnedResidual b = BinResidual(x, y, 64);
  const double mean = y.mean(), total = (y.array() - mean).square().sum();
  if (!(total > 0.0)) return -1.0;
  double between = 0.0;
  for (Eigen::Index i = 0; i < b.mean.size(); ++i) between += b.count(i) * (b.mean(i) - mean) * (b.mean(i) - mean);
  return between / total;
}

Eigen::VectorXd Folded(const Eigen::VectorXd& x, double period) {
  return x.unaryExpr([period](double v) {
    const double r = std::fmod(v, period);
    return r < 0.0 ? r + period : r;
  });
}

std::vector<EvidenceAxis> EvidenceAxes(const DiagnosisSignals& s, const DiagnosedEffect& e, const std::string& unit,
                                       const std::string& position_unit) {
  std::vector<EvidenceAxis> axes;
  if (const auto p = e.parameters.find("period"); p != e.parameters.end() && p->second > 0.0) {
    const std::string period = position_unit == "m" ? fmt::format("{:.4g} mm", 1e3 * p->second)
                                                    : fmt::format("{:.4g} {}", p->second, position_unit);
    axes.push_back({fmt::format("position modulo the period {} [{}]", period, position_unit),
                    Folded(s.position, p->second), true});
  }
  if (const auto f = e.parameters.find("frequency_hz"); f != e.parameters.end() && f->second > 0.0) {
    axes.push_back({fmt::format("time modulo the period 1/{:.6g} Hz [s]", f->second), Folded(s.time, 1.0 / f->second),
                    true});
  }
  axes.push_back({fmt::format("position [{}]", position_unit), s.position});
  axes.push_back({fmt::format("velocity [{}/s]", position_unit), s.velocity});
  axes.push_back({fmt::format("acceleration [{}/s²]", position_unit), s.acceleration});
  if (s.logged_command.size() == s.time.size()) {
    axes.push_back({fmt::format("logged command [{}]", unit), s.logged_command});
  }
  if (s.model_output.size() == s.time.size()) axes.push_back({fmt::format("model output [{}]", unit), s.model_output});
  axes.push_back({"time [s]", s.time});
  return axes;
}

// The bins' centres and means where a bin holds samples.
Series BinnedSeries(const Eigen::VectorXd& x, const Eigen::VectorXd& y, const std::string& label) {
  const BinnedResidual b = BinResidual(x, y, 64);
  Series s{{}, {}, label, "lines"};
  for (Eigen::Index i = 0; i < b.centers.size(); ++i) {
    if (b.count(i) > 0) {
      s.x.push_back(b.centers(i));
      s.y.push_back(b.mean(i));
    }
  }
  return s;
}

}  // namespace

Figure EffectEvidenceFigure(const DiagnosedComparison& compared, std::size_t k, const std::string& unit,
                            const std::string& position_unit, const std::string& file) {
  if (!compared.diagnosis || k >= compared.diagnosis->effects.size()) {
    throw std::invalid_argument(fmt::format("EffectEvidenceFigure: no ranked effect {}", k));
  }
  const DiagnosisResult& diagnosis = *compared.diagnosis;
  const DiagnosedEffect& e = diagnosis.effects[k];
  const DiagnosisSignals& s = compared.signals;
  const EffectRegressors reg = BuildEffectRegressors({e.effect, e.parameters}, s);
  const Eigen::VectorXd contribution = reg.columns * e.coefficients;
  const Eigen::VectorXd partial = s.residual - PredictCorrection(diagnosis, s, compared.base) + contribution;
  std::vector<EvidenceAxis> axes = EvidenceAxes(s, e, unit, position_unit);
  std::size_t best = axes.size();
  double best_share = -1.0;
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const double share = BinnedShare(axes[i].values, contribution);
    const double margin = (best < axes.size() && axes[best].folded && !axes[i].folded) ? 0.05 : 0.0;
    if (share > best_share + margin) {
      best = i;
      best_share = share;
    }
  }
  if (best == axes.size()) throw std::invalid_argument("EffectEvidenceFigure: every axis is constant");
  const EvidenceAxis& axis = axes[best];
  Figure f{file,
           fmt::format("{}. {}: {:.1f} % of the remaining held-out residual, against {}", k + 1, e.effect,
                       100.0 * e.score, axis.label.substr(0, axis.label.rfind(" ["))),
           axis.label, fmt::format("residual [{}]", unit), {}};
  f.series.push_back({ToStd(axis.values), ToStd(partial), "residual less the other effects", "dots"});
  f.series.push_back(BinnedSeries(axis.values, partial, "its binned mean"));
  f.series.push_back(BinnedSeries(axis.values, contribution, "fitted " + e.effect));
  if (axis.label == "time [s]") f.x_link = "time";
  // The y range of 99.8 % of the partial residual (and all of the fit): a few outliers do not flatten the shape.
  std::vector<double> sorted = ToStd(partial);
  std::sort(sorted.begin(), sorted.end());
  const double lo = sorted[sorted.size() / 1000], hi = sorted[sorted.size() - 1 - sorted.size() / 1000];
  const double pad = 0.05 * (hi - lo);
  f.y_range = {std::min(lo, contribution.minCoeff()) - pad, std::max(hi, contribution.maxCoeff()) + pad};
  return f;
}

void AddBeforeAfterFigures(HtmlReport* report, const fs::path& out, const std::string& prefix,
                           const std::string& record, const MeasurementLog& log, const ComparedOutput& before,
                           const ComparedOutput& after, const std::string& position_column) {
  const auto t = ToStd(log.time());
  const std::string unit = before.unit;
  Figure overlay{prefix + "model_vs_measurement.png",
                 fmt::format("{}: measured {} vs model, before (step 0) and after (improved)", record, before.connector),
                 "time [s]", fmt::format("{} [{}]", before.connector, unit), {}};
  overlay.series.push_back({t, ToStd(before.measured), "measured (" + before.column + ")", "lines"});
  overlay.series.push_back({t, ToStd(before.model), "model before", "lines"});
  overlay.series.push_back({t, ToStd(after.model), "model after", "lines"});
  overlay.x_link = prefix + "time";
  report->AddFigure(overlay, out);

  const auto r_before = ToStd(before.residual()), r_after = ToStd(after.residual());
  Figure rt{prefix + "residual_vs_time.png", record + ": residual against time, before vs after", "time [s]",
            fmt::format("measured − model [{}]", unit), {}};
  rt.series.push_back({t, r_before, "before", "lines"});
  rt.series.push_back({t, r_after, "after", "lines"});
  rt.x_link = prefix + "time";
  report->AddFigure(rt, out);
  // The residual against a logged column (position, velocity), before and after on the same axes.
  const auto against = [&](const std::string& column, const std::string& quantity, const std::string& axis_unit) {
    if (!log.has_column(column)) return;
    const auto abscissa = ToStd(log.column(column));
    Figure f{fmt::format("{}residual_vs_{}.png", prefix, quantity),
             fmt::format("{}: residual against {}, before vs after", record, quantity),
             fmt::format("{} [{}]", quantity, axis_unit), fmt::format("residual [{}]", unit), {}};
    f.series.push_back({abscissa, r_before, "before", "dots"});
    f.series.push_back({abscissa, r_after, "after", "dots"});
    report->AddFigure(f, out);
  };
  const std::string position_unit = PositionUnitToken(position_column);
  against(position_column, "position", position_unit);
  against(DerivedVelocityColumn(position_column), "velocity", position_unit + "/s");
}

}  // namespace mb
