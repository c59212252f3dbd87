#include "tools/report/residual_figures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/periodogram.h"
#include "models/diagnosis/signal_processing.h"
#include "tools/workflow/suggest.h"

namespace mb {

namespace fs = std::filesystem;

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

namespace {

// A residual axis that a few edge samples do not set (issue 40, item 8: a 150 N spike at the record's end flattened
// ±4 N of structure): the 0.1–99.9 % range of `y`, padded by a tenth, when samples lie beyond it; the figure's title
// then says how many and how far. The full data stay in the figure's series (the interactive chart zooms out).
void RobustResidualAxis(const Eigen::VectorXd& y, Figure* f) {
  if (y.size() < 100) return;
  std::vector<double> sorted = ToStd(y);
  std::sort(sorted.begin(), sorted.end());
  const std::size_t tail = sorted.size() / 1000;
  const double lo = sorted[tail], hi = sorted[sorted.size() - 1 - tail], pad = 0.1 * (hi - lo);
  if (!(hi > lo)) return;
  const double bottom = lo - pad, top = hi + pad;
  const auto outside = std::count_if(sorted.begin(), sorted.end(), [&](double v) { return v < bottom || v > top; });
  if (outside == 0) return;
  f->y_range = {bottom, top};
  f->title += fmt::format(" — {} sample(s) beyond the axis, from {:.4g} to {:.4g}", outside, sorted.front(),
                          sorted.back());
}

}  // namespace

void AddResidualFigures(HtmlReport* report, const fs::path& out, const MeasurementLog& log,
                        const ComparedOutput& before, const Eigen::VectorXd& residual_after,
                        const std::string& position_column) {
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
  RobustResidualAxis(residual_after, &rt);
  report->AddFigure(rt, out);
  if (log.has_column(position_column)) {
    Figure rx{"residual_vs_position.png", "Residual against position", "position [m]",
              fmt::format("residual [{}]", before.unit), {}};
    rx.series.push_back({ToStd(log.column(position_column)), ToStd(residual_after), "residual", "dots"});
    RobustResidualAxis(residual_after, &rx);
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
    RobustResidualAxis(residual_after, &rv);
    report->AddFigure(rv, out);
  }
  if (log.has_column(acceleration_column)) {
    Figure ra{"residual_vs_acceleration.png", "Residual against acceleration (a slope: mass mismatch)",
              "acceleration [m/s²]", fmt::format("residual [{}]", before.unit), {}};
    ra.series.push_back({ToStd(log.column(acceleration_column)), ToStd(residual_after), "samples", "dots"});
    RobustResidualAxis(residual_after, &ra);
    report->AddFigure(ra, out);
  }
}

namespace {

constexpr const char* kTimeAxis = "time [s]";

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
  axes.push_back({kTimeAxis, s.time});
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

namespace {

// The effect's regressor as an axis when it is the output's error itself (EffectTraits::regressor_is_error: ŷ(t − d)
// − ŷ(t) of a delay, the lagged model output less the model output; q·round(ŷ/q) − ŷ of a quantization), one column:
// the evidence is then a line of slope = its coefficient through the origin. Labelled by the registry's formula.
std::optional<EvidenceAxis> RegressorAxis(const EffectType* type, const EffectRegressors& reg,
                                          const std::string& unit) {
  if (type == nullptr || !type->traits.regressor_is_error || reg.columns.cols() != 1) return std::nullopt;
  const std::string formula = type->regressor_formula.substr(0, type->regressor_formula.find(" ("));
  return EvidenceAxis{fmt::format("its regressor {} [{}]", formula, unit), reg.columns.col(0), true};
}

// Whether the effect's regressors change when the clock moves (the record's time shifted by its span): a change of
// a parameter in time (a mass picked up at t_c, a drifting friction), whose evidence is the residual against time.
// A vibration (periodic in t) has its folded axis instead.
bool ChangesWithTheClock(const DiagnosedEffect& e, const EffectType* type, const DiagnosisSignals& s,
                         const EffectRegressors& reg) {
  if (type == nullptr || type->traits.periodicity == Periodicity::kTime || s.time.size() < 2) return false;
  DiagnosisSignals shifted = s;
  shifted.time.array() += 2.0 * (s.time(s.time.size() - 1) - s.time(0));
  try {
    const EffectRegressors moved = BuildEffectRegressors({e.effect, e.parameters}, shifted);
    if (moved.columns.rows() != reg.columns.rows() || moved.columns.cols() != reg.columns.cols()) return true;
    return (moved.columns - reg.columns).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + reg.columns.cwiseAbs().maxCoeff());
  } catch (const std::invalid_argument&) {
    return false;
  }
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
  const EffectType* type = EffectRegistry::Global().Find(e.effect);
  const EffectRegressors reg = BuildEffectRegressors({e.effect, e.parameters}, s);
  const Eigen::VectorXd contribution = EffectContribution(diagnosis, e, s);
  const Eigen::VectorXd partial = s.residual - PredictCorrection(diagnosis, s, compared.base) + contribution;
  std::vector<EvidenceAxis> axes = EvidenceAxes(s, e, unit, position_unit);
  if (auto axis = RegressorAxis(type, reg, unit)) axes.insert(axes.begin(), std::move(*axis));
  const bool in_time = ChangesWithTheClock(e, type, s, reg);
  std::size_t best = axes.size();
  double best_share = -1.0;
  for (std::size_t i = 0; i < axes.size(); ++i) {
    if (in_time) {  // a change in time is seen against time, whatever else its contribution follows
      if (axes[i].label == kTimeAxis) best = i;
      continue;
    }
    const double share = BinnedShare(axes[i].values, contribution);
    const double margin = (best < axes.size() && axes[best].folded && !axes[i].folded) ? 0.05 : 0.0;
    if (share > best_share + margin) {
      best = i;
      best_share = share;
    }
  }
  if (best == axes.size()) throw std::invalid_argument("EffectEvidenceFigure: every axis is constant");
  const EvidenceAxis& axis = axes[best];
  const std::vector<const DiagnosedEffect*> order = EffectsInApplicationOrder(diagnosis);
  const auto number = std::find(order.begin(), order.end(), &e) - order.begin() + 1;  // as compare's table numbers it
  Figure f{file,
           fmt::format("{}. {}: {:.1f} % of the remaining held-out residual, against {}", number, e.effect,
                       100.0 * e.score, axis.label.substr(0, axis.label.rfind(" ["))),
           axis.label, fmt::format("residual [{}]", unit), {}};
  if (in_time) {
    // A change in time: the residual and the fit as records (a few pixels' extremes each), the instants marked.
    f.series.push_back({ToStd(axis.values), ToStd(partial), "residual less the other effects", "lines"});
    f.series.push_back({ToStd(axis.values), ToStd(contribution), "fitted " + e.effect, "lines"});
    for (const auto& p : type->parameters) {
      const auto value = e.parameters.find(p.name);
      if (p.unit == "s" && value != e.parameters.end()) {
        f.x_marks.emplace_back(value->second, fmt::format("{} {:.4g} s", p.name, value->second));
      }
    }
  } else {
    f.series.push_back({ToStd(axis.values), ToStd(partial), "residual less the other effects", "dots"});
    f.series.push_back(BinnedSeries(axis.values, partial, "its binned mean"));
    f.series.push_back(BinnedSeries(axis.values, contribution, "fitted " + e.effect));
  }
  if (axis.label == kTimeAxis) f.x_link = "time";
  // The y range of 99.8 % of the partial residual (and all of the fit): a few outliers do not flatten the shape.
  std::vector<double> sorted = ToStd(partial);
  std::sort(sorted.begin(), sorted.end());
  const double lo = sorted[sorted.size() / 1000], hi = sorted[sorted.size() - 1 - sorted.size() / 1000];
  const double pad = 0.05 * (hi - lo);
  f.y_range = {std::min(lo, contribution.minCoeff()) - pad, std::max(hi, contribution.maxCoeff()) + pad};
  return f;
}

std::string EffectShareAndConfidence(const DiagnosedEffect& effect) {
  std::string text = fmt::format("Share: {:.1f} % of the remaining held-out residual explained (cumulative {:.1f} %).",
                                 100.0 * effect.score, 100.0 * effect.cumulative_share);
  const Eigen::Index n = effect.coefficients.size();
  if (n == 0) return text + " No coefficient reported.";
  text += n == 1 ? " Coefficient of the final joint fit, 95 % interval: "
                 : " Coefficients of the final joint fit, 95 % intervals: ";
  int significant = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    std::string name = static_cast<std::size_t>(i) < effect.column_names.size()
                           ? effect.column_names[static_cast<std::size_t>(i)]
                           : fmt::format("c{}", i + 1);
    if (name.rfind(effect.effect + ".", 0) == 0) name.erase(0, effect.effect.size() + 1);
    const double value = effect.coefficients(i);
    const double half = i < effect.coefficient_std.size() ? 1.96 * effect.coefficient_std(i)
                                                          : std::numeric_limits<double>::quiet_NaN();
    const bool holds_zero = !(std::abs(value) > half);  // an unknown interval counts as holding 0
    significant += holds_zero ? 0 : 1;
    text += fmt::format("{}{} = {:.4g} ± {:.2g}{}", i ? ", " : "", name, value, half, holds_zero ? " (holds 0)" : "");
  }
  return text + (n == 1 ? (significant ? "; significant." : "; not significant: the interval holds 0.")
                        : fmt::format("; {} of {} significant.", significant, n));
}

Figure PositionPeriodogramFigure(const DiagnosedComparison& compared, const std::string& position_unit,
                                 const std::string& file) {
  if (!compared.diagnosis) throw std::invalid_argument("PositionPeriodogramFigure: no diagnosis");
  const DiagnosisResult& diagnosis = *compared.diagnosis;
  const DiagnosisSignals& s = compared.signals;
  const CatalogueOptions catalogue{};
  // What the diagnosis searched periods in: the residual less the base's corrections and the friction-law
  // replacements (here from the final joint fit: diagnosis.cc refits them alone first).
  Eigen::VectorXd searched = s.residual;
  if (diagnosis.base_coefficients.size() > 0 && compared.base.columns.cols() == diagnosis.base_coefficients.size() &&
      compared.base.columns.rows() == s.size()) {
    searched -= compared.base.columns * diagnosis.base_coefficients;
  }
  for (const auto& e : diagnosis.effects) {
    if (std::find(diagnosis.friction_law.begin(), diagnosis.friction_law.end(), e.effect) ==
        diagnosis.friction_law.end()) {
      continue;
    }
    searched -= BuildEffectRegressors({e.effect, e.parameters}, s).columns * e.coefficients;
  }
  // The samples in motion, as the diagnosis's search took them (effect_proposal.cc, MovingSamples).
  const double dead_band = catalogue.dead_band_fraction * s.velocity.cwiseAbs().maxCoeff();
  std::vector<Eigen::Index> moving;
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (std::abs(s.velocity(i)) > dead_band) moving.push_back(i);
  }
  Eigen::VectorXd x = s.position, r = searched;
  if (4 * static_cast<Eigen::Index>(moving.size()) >= s.size()) {
    x.resize(static_cast<Eigen::Index>(moving.size()));
    r.resize(x.size());
    for (std::size_t k = 0; k < moving.size(); ++k) {
      x(static_cast<Eigen::Index>(k)) = s.position(moving[k]);
      r(static_cast<Eigen::Index>(k)) = searched(moving[k]);
    }
  }
  PeriodogramOptions po = catalogue.position_periodogram;
  if (po.max_period <= 0.0) po.max_period = (x.maxCoeff() - x.minCoeff()) / catalogue.min_position_cycles;
  const Periodogram pg = PositionPeriodogram(x, r, po);
  const auto shown = [&](double period) {
    return position_unit == "m" ? fmt::format("{:.4g} mm", 1e3 * period)
                                : fmt::format("{:.4g} {}", period, position_unit);
  };
  Figure f{file,
           fmt::format("Position-domain periodogram of the residual (samples in motion, periods up to the travel/{:g})",
                       catalogue.min_position_cycles),
           fmt::format("period [{}]", position_unit), "share of the variance explained", {}};
  f.log_x = true;
  f.series.push_back({ToStd(pg.periods), ToStd(pg.power), "floating-mean Lomb–Scargle", "lines"});
  for (const auto& e : diagnosis.effects) {  // the periods the ranking chose, as the text names them
    const auto period = e.parameters.find("period");
    if (period != e.parameters.end()) f.x_marks.emplace_back(period->second, e.effect + " " + shown(period->second));
  }
  if (!diagnosis.position_peaks.empty()) {
    const PeriodogramPeak& top = diagnosis.position_peaks.front();
    f.x_marks.emplace_back(top.period, fmt::format("strongest peak (notes) {}", shown(top.period)));
  }
  return f;
}

void AddEffectEvidence(HtmlReport* report, const fs::path& out, const DiagnosedComparison& compared,
                       const std::string& unit, const std::string& position_unit) {
  if (!compared.diagnosis) return;
  const DiagnosisResult& diagnosis = *compared.diagnosis;
  // In the order the table lists them and --suggest and improve apply them (the friction-law replacements first).
  const std::vector<const DiagnosedEffect*> order = EffectsInApplicationOrder(diagnosis);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const DiagnosedEffect& e = *order[k];
    const auto index = static_cast<std::size_t>(order[k] - diagnosis.effects.data());
    report->Paragraph(fmt::format("{}. {}: {}", k + 1, e.effect, e.description));
    report->Paragraph(EffectShareAndConfidence(e));
    try {
      report->AddFigure(
          EffectEvidenceFigure(compared, index, unit, position_unit, fmt::format("effect_{}.png", k + 1)), out);
    } catch (const std::invalid_argument& error) {
      report->Warning(fmt::format("No evidence figure for {}: {}", e.effect, error.what()));
    }
  }
  if (diagnosis.position_peaks.empty()) return;  // no position periods searched
  try {
    const Figure f = PositionPeriodogramFigure(compared, position_unit, "position_periodogram.png");
    std::string marks;
    for (const auto& [x, label] : f.x_marks) marks += (marks.empty() ? "" : "; ") + label;
    report->Paragraph("The position periods, searched as the diagnosis searched them: the residual less the base's "
                      "corrections and the friction-law replacements, its samples in motion. Marked: " + marks + ".");
    report->AddFigure(f, out);
  } catch (const std::invalid_argument& error) {
    report->Warning(fmt::format("No position periodogram: {}", error.what()));
  }
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

Figure ResidualSpectrumFigure(const Eigen::VectorXd& time, const Eigen::VectorXd& before, const Eigen::VectorXd& after,
                              const std::string& unit, const std::string& file) {
  if (before.size() != time.size() || after.size() != time.size()) {
    throw std::invalid_argument(fmt::format("ResidualSpectrumFigure: {} times, residuals of {} and {} samples",
                                            time.size(), before.size(), after.size()));
  }
  const double step = MedianTimeStep(time);
  Figure f{file, "Residual's amplitude spectrum, before vs after (Welch: Hann, 50 % overlap)", "frequency [Hz]",
           fmt::format("amplitude spectral density [{}/√Hz]", unit), {}};
  f.log_y = true;
  const auto add = [&](const Eigen::VectorXd& r, const std::string& label) {
    const PowerSpectrum p = WelchPowerSpectrum(r, step);
    const double rms = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    Series series{{}, {}, fmt::format("{} (RMS {:.4g} {})", label, rms, unit), "lines"};
    for (Eigen::Index i = 1; i < p.frequency_hz.size(); ++i) {  // 0 Hz: the mean, removed
      series.x.push_back(p.frequency_hz(i));
      series.y.push_back(std::sqrt(p.density(i)));
    }
    f.series.push_back(std::move(series));
  };
  add(before, "before");
  add(after, "after");
  return f;
}

ResidualHistogram HistogramOfResiduals(const Eigen::VectorXd& before, const Eigen::VectorXd& after, std::size_t bins) {
  if (bins == 0) throw std::invalid_argument("HistogramOfResiduals: bins must be >= 1");
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Eigen::VectorXd* r : {&before, &after}) {
    for (Eigen::Index i = 0; i < r->size(); ++i) {
      if (std::isfinite((*r)(i))) {
        lo = std::min(lo, (*r)(i));
        hi = std::max(hi, (*r)(i));
      }
    }
  }
  if (!(lo <= hi)) throw std::invalid_argument("HistogramOfResiduals: no finite residual");
  if (!(hi > lo)) {
    lo -= 0.5;
    hi += 0.5;
  }
  ResidualHistogram h;
  for (std::size_t i = 0; i <= bins; ++i) {
    h.edges.push_back(i == bins ? hi : lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(bins));
  }
  const auto count = [&](const Eigen::VectorXd& r) {
    std::vector<std::size_t> c(bins, 0);
    for (Eigen::Index i = 0; i < r.size(); ++i) {
      if (!std::isfinite(r(i))) continue;
      const double f = (r(i) - lo) / (hi - lo) * static_cast<double>(bins);
      ++c[std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, f)))];
    }
    return c;
  };
  h.before = count(before);
  h.after = count(after);
  return h;
}

Figure ResidualHistogramFigure(const ResidualHistogram& histogram, const std::string& unit, const std::string& file) {
  Figure f{file, "Residual's distribution, before vs after (samples per bin)", fmt::format("residual [{}]", unit),
           "samples per bin", {}};
  const auto steps = [&](const std::vector<std::size_t>& counts, const std::string& label) {
    Series s{histogram.edges, {}, label, "steps"};
    for (std::size_t c : counts) s.y.push_back(static_cast<double>(c));
    if (!counts.empty()) s.y.push_back(static_cast<double>(counts.back()));  // the last bin's right edge
    return s;
  };
  f.series = {steps(histogram.before, "before"), steps(histogram.after, "after")};
  return f;
}

void AddResidualSpectrumAndHistogram(HtmlReport* report, const fs::path& out, const std::string& prefix,
                                     const std::string& record, const MeasurementLog& log,
                                     const ComparedOutput& before, const ComparedOutput& after) {
  const Eigen::VectorXd r_before = before.residual(), r_after = after.residual();
  try {
    Figure spectrum = ResidualSpectrumFigure(log.time(), r_before, r_after, before.unit,
                                             prefix + "residual_spectrum.png");
    spectrum.title = record + ": " + spectrum.title;
    report->AddFigure(spectrum, out);
  } catch (const std::invalid_argument& error) {
    report->Warning(fmt::format("No spectrum of the residual: {}", error.what()));
  }
  try {
    const auto bins = static_cast<std::size_t>(
        std::clamp(std::sqrt(static_cast<double>(r_before.size())), 10.0, 100.0));
    Figure histogram = ResidualHistogramFigure(HistogramOfResiduals(r_before, r_after, bins), before.unit,
                                               prefix + "residual_histogram.png");
    histogram.title = record + ": " + histogram.title;
    report->AddFigure(histogram, out);
  } catch (const std::invalid_argument& error) {
    report->Warning(fmt::format("No distribution of the residual: {}", error.what()));
  }
}

}  // namespace mb
