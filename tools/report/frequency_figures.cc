#include "tools/report/frequency_figures.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "engine/linearization.h"
#include "engine/units.h"
#include "models/diagnosis/frequency_response.h"
#include "models/diagnosis/signal_processing.h"  // MedianTimeStep

namespace mb {

namespace fs = std::filesystem;

namespace {

MotionQuantity QuantityOf(const ExternalInput& in) {
  return in.quantity != MotionQuantity::kOther ? in.quantity : QuantityOfUnit(in.unit);
}

// Which input drives the response: the log column read as the input, and per model input the power of j2πf its
// response is multiplied by (none: the input is held at its operating value).
struct Excitation {
  std::string column;
  std::string name;  // as the report says it
  std::vector<std::optional<int>> order;
};

std::optional<Excitation> ChooseExcitation(ExperimentMode mode, const Diagram& d, const MeasurementLog& log) {
  const auto& inputs = d.inputs();
  Excitation e{{}, {}, std::vector<std::optional<int>>(inputs.size())};
  for (std::size_t k = 0; k < inputs.size() && e.column.empty(); ++k) {
    const bool position = QuantityOf(inputs[k]) == MotionQuantity::kPosition;
    if (log.has_column(inputs[k].measurement) && (mode == ExperimentMode::kSimulation || position)) {
      e.column = inputs[k].measurement;
      e.name = fmt::format("{} ({})", inputs[k].name, inputs[k].measurement);
      e.order[k] = 0;
    }
  }
  if (e.column.empty()) return std::nullopt;
  if (mode == ExperimentMode::kEquationError) {  // the motion inputs are the position and its derivatives
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const MotionQuantity q = QuantityOf(inputs[k]);
      if (q == MotionQuantity::kVelocity) e.order[k] = 1;
      if (q == MotionQuantity::kAcceleration) e.order[k] = 2;
    }
  }
  return e;
}

// Each input's mean over the log; a velocity's median speed.
OperatingPoint RecordOperatingPoint(const Diagram& d, const MeasurementLog& log) {
  OperatingPoint point;
  for (const auto& in : d.inputs()) {
    if (!log.has_column(in.measurement)) continue;
    Eigen::VectorXd v = log.column(in.measurement);
    if (QuantityOf(in) == MotionQuantity::kVelocity) {
      v = v.cwiseAbs();
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      point.inputs[in.name] = v(v.size() / 2);
    } else {
      point.inputs[in.name] = v.mean();
    }
  }
  return point;
}

// The rows of the longest contiguous segment of the log [first, first + count).
std::pair<Eigen::Index, Eigen::Index> LongestSegment(const MeasurementLog& log) {
  const auto& starts = log.segment_starts();
  std::pair<Eigen::Index, Eigen::Index> best{0, 0};
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const Eigen::Index end = i + 1 < starts.size() ? starts[i + 1] : log.rows();
    if (end - starts[i] > best.second) best = {starts[i], end - starts[i]};
  }
  return best;
}

// The largest power of two ≤ 2N/9 (about eight half-overlapping segments, tfestimate's default), within [64, 4096].
Eigen::Index SegmentLength(Eigen::Index n) {
  Eigen::Index m = 64;
  while (2 * m <= 2 * n / 9 && 2 * m <= 4096) m *= 2;
  return m;
}

// The sentence on where the model's gain and the measured one part, over the bins of coherence ≥ kTrustedCoherence.
std::string Agreement(const Eigen::VectorXd& f, const BodeData& measured, const BodeData& model,
                      const Eigen::VectorXd& coherence) {
  std::vector<double> gaps;
  double worst = 0.0, worst_f = 0.0;
  for (Eigen::Index k = 0; k < f.size(); ++k) {
    if (coherence(k) < kTrustedCoherence) continue;
    const double gap = measured.gain_db(k) - model.gain_db(k);
    if (!std::isfinite(gap)) continue;
    gaps.push_back(std::abs(gap));
    if (std::abs(gap) > std::abs(worst)) worst = gap, worst_f = f(k);
  }
  if (gaps.empty()) {
    return fmt::format("The coherence stays below {} at every frequency: the output is not linear in this input over "
                       "the record (noise, a nonlinearity such as friction, or another input dominates), so the "
                       "measured response says little; compare the time-domain views instead.",
                       kTrustedCoherence);
  }
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  return fmt::format("Where the coherence is at least {} ({} of {} frequencies), the measured gain differs from the "
                     "model's by {:.2g} dB (median) and by {:+.3g} dB at most, at {:.4g} Hz ({} there).",
                     kTrustedCoherence, gaps.size(), f.size(), gaps[gaps.size() / 2], worst, worst_f,
                     worst > 0 ? "the stage responds more than the model" : "the model responds more than the stage");
}

// How each model input moves with the excitation, per frequency (none: held at its operating value): 1 for the
// excitation itself; for a velocity or acceleration derived from it, the derivation's own response measured on the
// log (H1 from the excitation's column to the input's: the low-pass and differences the intake applied), else the
// ideal (j2πf)^order.
std::vector<std::optional<Eigen::VectorXcd>> InputRelations(const Diagram& d, const MeasurementLog& log,
                                                           const Excitation& excitation, const Eigen::VectorXd& f,
                                                           Eigen::Index first, Eigen::Index count, double dt,
                                                           Eigen::Index m) {
  std::vector<std::optional<Eigen::VectorXcd>> relations(excitation.order.size());
  for (std::size_t k = 0; k < relations.size(); ++k) {
    if (!excitation.order[k]) continue;
    const std::string& column = d.inputs()[k].measurement;
    if (*excitation.order[k] == 0) {
      relations[k] = Eigen::VectorXcd::Ones(f.size());
    } else if (log.has_column(column)) {
      relations[k] = EstimateFrequencyResponse(log.column(excitation.column).segment(first, count),
                                               log.column(column).segment(first, count), dt, m)
                         .response.tail(f.size());
    } else {
      relations[k] = (2.0 * std::numbers::pi * f).unaryExpr([&](double w) {
        return std::pow(std::complex<double>(0.0, w), *excitation.order[k]);
      });
    }
  }
  return relations;
}

// The linearised model's response to the excitation (Σ over its inputs of their response times their relation to
// the excitation), or none when it does not respond (every path from the input runs through a discrete block, which
// the linearisation holds).
std::optional<Eigen::VectorXcd> LinearisedResponse(const Diagram& d, const MeasurementLog& log,
                                                   const std::vector<std::optional<Eigen::VectorXcd>>& relations,
                                                   int output, const Eigen::VectorXd& f, int* states) {
  const LinearModel linear = Linearize(d, RecordOperatingPoint(d, log));
  *states = static_cast<int>(linear.a.rows());
  Eigen::VectorXcd model = Eigen::VectorXcd::Zero(f.size());
  for (std::size_t k = 0; k < relations.size(); ++k) {
    if (relations[k]) model += linear.FrequencyResponse(output, static_cast<int>(k), f).cwiseProduct(*relations[k]);
  }
  if (!model.allFinite() || model.cwiseAbs().maxCoeff() == 0.0) return std::nullopt;
  return model;
}

struct BodeCurve {
  BodeData bode;
  std::string label;
};

void AddBodeFigures(HtmlReport* report, const fs::path& out, const Eigen::VectorXd& f,
                    const std::vector<BodeCurve>& curves, const Eigen::VectorXd& coherence, const std::string& ratio) {
  const std::vector<double> x(f.begin(), f.end());
  const auto series = [&](const Eigen::VectorXd& y, const std::string& label) {
    return Series{x, std::vector<double>(y.begin(), y.end()), label, "lines"};
  };
  Figure gain{"frequency_response_gain.png", fmt::format("Gain of {}: measured vs model", ratio), "frequency [Hz]",
              "gain [dB]", {}};
  Figure phase{"frequency_response_phase.png", fmt::format("Phase of {}", ratio), "frequency [Hz]", "phase [deg]", {}};
  for (const auto& curve : curves) {
    gain.series.push_back(series(curve.bode.gain_db, curve.label));
    phase.series.push_back(series(curve.bode.phase_deg, curve.label));
  }
  Figure c{"frequency_response_coherence.png", "Coherence of the measured response (1: the output is linear in the input)",
           "frequency [Hz]", "coherence γ²", {series(coherence, "γ²")}};
  c.series.push_back({{x.front(), x.back()}, {kTrustedCoherence, kTrustedCoherence}, "trusted above", "lines"});
  c.y_range = std::pair{0.0, 1.0};
  for (Figure* figure : {&gain, &phase, &c}) {
    figure->log_x = true;
    figure->x_link = "frequency";
    report->AddFigure(*figure, out);
  }
}

}  // namespace

void AddFrequencyResponseFigures(HtmlReport* report, const fs::path& out, ExperimentMode mode,
                                 const nlohmann::json& diagram, const fs::path& base_directory,
                                 const MeasurementLog& log, const ComparedOutput& output) {
  try {
    const Diagram d = BuildDiagram(diagram, base_directory, "the fitted diagram");
    const auto excitation = ChooseExcitation(mode, d, log);
    const auto& outputs = d.outputs();
    const auto out_it =
        std::find_if(outputs.begin(), outputs.end(), [&](const auto& o) { return o.name == output.connector; });
    if (!excitation || out_it == outputs.end()) {
      report->Paragraph("No frequency view: the log holds no column of the diagram's inputs to excite it with.");
      return;
    }
    const auto [first, count] = LongestSegment(log);
    if (count < 64) {
      report->Paragraph(fmt::format("No frequency view: the longest gap-free stretch of the log has {} samples "
                                    "(at least 64 are needed).", count));
      return;
    }
    const double dt = MedianTimeStep(log.time().segment(first, count));
    const Eigen::Index m = SegmentLength(count);
    const auto input = log.column(excitation->column).segment(first, count);
    const FrequencyResponseEstimate h1 = EstimateFrequencyResponse(input, output.measured.segment(first, count), dt, m);
    const FrequencyResponseEstimate simulated =
        EstimateFrequencyResponse(input, output.model.segment(first, count), dt, m);
    const Eigen::Index bins = h1.frequency_hz.size() - 1;  // 0 Hz has no place on a log axis
    const Eigen::VectorXd f = h1.frequency_hz.tail(bins), coherence = h1.coherence.tail(bins);
    const BodeData measured = ToBode(h1.response.tail(bins)), model = ToBode(simulated.response.tail(bins));
    std::vector<BodeCurve> curves{{measured, "measured (H1)"}, {model, "model, simulated on the same input (H1)"}};
    int states = 0;
    const auto linearised =
        LinearisedResponse(d, log, InputRelations(d, log, *excitation, f, first, count, dt, m),
                           static_cast<int>(out_it - outputs.begin()), f, &states);
    if (linearised) curves.push_back({ToBode(*linearised), "model, linearised"});
    const std::string ratio = fmt::format("{} / {}", output.connector, excitation->name);
    AddBodeFigures(report, out, f, curves, coherence, ratio);
    report->Paragraph(fmt::format(
        "Welch's H1 estimates from {} to {}, measured and as the model simulates it ({} segments of {} samples, Hann, "
        "50 % overlap). {} {}",
        excitation->name, output.column, h1.segments, m, Agreement(f, measured, model, coherence),
        linearised ? fmt::format("The linearised model ({} continuous states; each input held at its mean over the "
                                 "record, a velocity at its median speed) is drawn too: where it leaves the simulated "
                                 "curve, the model's response depends on more than one operating point holds (its "
                                 "nonlinearity), or the record excites that band too little (see the coherence).",
                                 states)
                   : "The linearised model does not respond to this input: its paths from it run through discrete "
                     "blocks, which a linearisation holds (motionblocks linearize, as linmod)."));
  } catch (const std::exception& e) {
    report->Paragraph(fmt::format("No frequency view: {}", e.what()));
  }
}

}  // namespace mb
