// hysteresis: a force that follows the stroke since the last reversal, set by displacement and not by time or speed —
// a flexure, a preloaded guide, a friction damper's band, a cable, magnetic hysteresis. A Prandtl–Ishlinskii sum of
// stop operators, i.e. a generalised Maxwell-slip model: n elasto-slide elements, element i a spring of stiffness k_i
// that slides once it carries F_i = k_i·r_i (its break-away displacement r_i) (Brokate & Sprekels, Hysteresis and Phase
// Transitions, 1996, ch. 2; Al-Bender, Lampaert & Swevers, IEEE TAC 50(11), 2005). Linear in its weights, so it joins
// the forward selection and the held-out test like any term.
//
// Regressors s_i = (x − p_{r_i}(x))/r_i ∈ [−1, 1], p_r the play operator of half-width r (the stop operator over r),
// r_i on a log grid from min_breakaway to max_breakaway, i = 1..elements; coefficient i is F_i [N]. {min_breakaway
// [m] (0.5 % of the travel), max_breakaway [m] (10 % of the travel), elements (9)}. Read off the coefficients: the
// stroke after a reversal over which the force makes 90 % of its swing [m], the break-away force Σ F_i⁺ [N] (half the
// swing) and the initial stiffness Σ F_i⁺/r_i [N/m] (F⁺: the positive part — a Maxwell-slip element cannot push back).
// Proposed when the axis reverses at least twice. Block: hysteresis (blocks/hysteresis.cc), the same elements.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "hysteresis";
constexpr int kElements = 9;         // a factor 1.45 between neighbours
constexpr double kSwingShare = 0.9;  // the stroke reported: where the force has made this much of its swing

int Elements(const EffectInstance& e) {
  const auto it = e.parameters.find("elements");
  if (it == e.parameters.end()) return kElements;
  if (!(it->second >= 1.0 && it->second <= 50.0) || it->second != std::round(it->second)) {
    throw std::invalid_argument(fmt::format("effect '{}': parameter 'elements' must be an integer in 1..50", e.name));
  }
  return static_cast<int>(it->second);
}

// The break-away displacements r_1 < … < r_n [m]: log-spaced from min to max (min alone when n = 1).
std::vector<double> Breakaways(const EffectInstance& e) {
  const double lo = PositiveParameter(e, "min_breakaway"), hi = PositiveParameter(e, "max_breakaway");
  if (!(hi >= lo)) {
    throw std::invalid_argument(fmt::format("effect '{}': max_breakaway {} must be at least min_breakaway {}", e.name,
                                            hi, lo));
  }
  return LogSpaced(lo, hi, Elements(e));
}

EffectRegressors Columns(const EffectInstance& e, const DiagnosisSignals& s) {
  const std::vector<double> r = Breakaways(e);
  EffectRegressors out;
  out.columns.resize(s.position.size(), static_cast<Eigen::Index>(r.size()));
  for (std::size_t i = 0; i < r.size(); ++i) {
    out.columns.col(static_cast<Eigen::Index>(i)) = (s.position - PlayOperator(s.position, r[i])) / r[i];
    out.column_names.push_back(fmt::format("{}.r{}", e.name, i + 1));
  }
  return out;
}

// The stroke, break-away force and initial stiffness of the fitted elements (the header's formulas). After a reversal
// element i's force changes by 2·F_i over a stroke of 2·r_i, linearly: the swing at stroke u is Σ F_i⁺·min(u, 2r_i)/r_i.
std::map<std::string, double> ReadOff(const EffectInstance& e, const Eigen::VectorXd& coefficients) {
  const std::vector<double> r = Breakaways(e);
  std::map<std::string, double> out;
  if (coefficients.size() != static_cast<Eigen::Index>(r.size())) return out;
  double force = 0.0, stiffness = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double f = std::max(coefficients(static_cast<Eigen::Index>(i)), 0.0);
    force += f;
    stiffness += f / r[i];
  }
  if (!(force > 0.0)) return out;
  const auto swing = [&](double u) {
    double s = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      s += std::max(coefficients(static_cast<Eigen::Index>(i)), 0.0) * std::min(u, 2.0 * r[i]) / r[i];
    }
    return s;
  };
  // The swing is continuous and rises in u up to 2·r_n: bisection for kSwingShare of 2·Σ F⁺.
  double lo = 0.0, hi = 2.0 * r.back();
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (swing(mid) < kSwingShare * 2.0 * force ? lo : hi) = mid;
  }
  out["stroke"] = 0.5 * (lo + hi);
  out["breakaway_force"] = force;
  out["initial_stiffness"] = stiffness;
  return out;
}

int Reversals(const Eigen::VectorXd& sign) {
  int count = 0;
  double last = 0.0;
  for (Eigen::Index i = 0; i < sign.size(); ++i) {
    if (sign(i) == 0.0) continue;
    if (last != 0.0 && sign(i) != last) ++count;
    last = sign(i);
  }
  return count;
}

void Propose(ProposalContext& c) {
  if (!(c.max_speed() > 0.0) || !(c.position_span() > 0.0)) return;
  if (Reversals(SignDeadBand(c.signals().velocity, c.dead_band())) < 2) {
    c.Note("hysteresis not proposed: the axis reverses fewer than twice, and a loop needs both directions");
    return;
  }
  // In the position's own unit (m, rad, V): on EMPS's 0.25 m, 1.25 mm … 25 mm.
  c.Propose(kName, {{"min_breakaway", kHysteresisMinBreakawayShare * c.position_span()},
                    {"max_breakaway", kHysteresisMaxBreakawayShare * c.position_span()},
                    {"elements", static_cast<double>(kElements)}});
}

EffectType Hysteresis() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 47;
  t.physics = "the force follows the stroke since the last reversal, set by displacement and not by time or speed "
              "(hysteresis: a flexure, a preloaded guide, a friction damper's band, a cable, magnetic hysteresis); add a "
              "hysteresis block (Maxwell-slip elements)";
  t.regressor_formula = "(x − p_r(x))/r, p_r the play operator of half-width r, r on a log grid (Prandtl–Ishlinskii)";
  t.parameters = {{"min_breakaway", "m", "r₁: the smallest element's break-away displacement"},
                  {"max_breakaway", "m", "r_n: the largest element's break-away displacement"},
                  {"elements", "", "n: the elasto-slide elements, log-spaced (9 when absent)"},
                  {"stroke", "m", "read off the fit: the stroke after a reversal over which the force makes 90 % of its "
                                  "swing"},
                  {"breakaway_force", "N", "read off the fit: Σ F_i⁺, half the force's swing"},
                  {"initial_stiffness", "N/m", "read off the fit: Σ F_i⁺/r_i, the slope right after a reversal"}};
  t.regressors = Columns;
  t.derived_parameters = ReadOff;
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(hysteresis, mb::Hysteresis())
