// Forward selection (DiagnoseMissingEffects, steps 3–3b): each round adds the candidate whose columns, fitted jointly
// with the base's and the effects chosen before, leave the lowest block held-out error (near-ties within
// 0.1 % to the lower BIC); its score is 1 − MSE(S ∪ {c})/MSE(S). A candidate is chosen only when its gain reaches
// DiagnosisOptions::min_gain and is significant against the residual's autocorrelation (Diebold–Mariano on the
// held-out loss differences, batch-mean variance; family-wise, Bonferroni, for the pairs the grammar searched), an
// effect whose regressor is the error itself only with a coefficient near 1, and a pair that holds its multiplier × 1,
// or the same multiplier's pair of a modulator whose shape is a limit of its own (a step in a window), only when it
// beats that pair significantly. The friction-law replacements are searched first, in rounds of their
// own. Sources: DIAGNOSIS.md, "Naming the missing effect", steps 3–4, and "When the base model is wrong elsewhere"
// (significance); Brunton, Proctor & Kutz 2016 (SINDy: sparse selection from a candidate library); Schwarz 1978 (BIC);
// Diebold & Mariano, "Comparing predictive accuracy" (1995); Bonferroni's correction for many tests (Dunn 1961).
#include "models/diagnosis/forward_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/math/distributions/normal.hpp>

#include <fmt/format.h>

#include "models/diagnosis/effect_registry.h"

namespace mb::diagnosis_detail {
namespace {

// An effect whose regressor is the error itself (EffectTraits::regressor_is_error) must enter with a coefficient
// near 1; far from it, the column is only a nonlinear function of ŷ that happens to correlate with the residual (on
// EMPS: a 13 N "quantization step" with coefficient 0.2). An effect whose coefficient has a physical sign
// (EffectTraits::positive_coefficient: a drag) must enter with it. True, and a note, when it is dropped for that.
bool ImplausibleCoefficient(const Candidate& c, const RegressorMatrix& m, const BlockGrams& grams,
                            const std::vector<Eigen::Index>& trial, std::vector<std::string>* notes) {
  const EffectTraits& traits = c.type->traits;
  if (!traits.regressor_is_error && !traits.positive_coefficient) return false;
  double sse = 0.0;
  const Eigen::VectorXd theta = grams.Fit(trial, &sse);
  const double coefficient = theta(theta.size() - 1) / m.scale(trial.back());
  const bool plausible = traits.regressor_is_error ? coefficient >= 0.5 && coefficient <= 1.5 : coefficient > 0.0;
  if (plausible) return false;
  std::string parameters;
  for (const auto& [key, value] : c.effect.parameters) {
    parameters += fmt::format("{}{} = {:.4g}", parameters.empty() ? "" : ", ", key, value);
  }
  notes->push_back(fmt::format("{}{}{}{} dropped: it fits with coefficient {:.3g} where the effect itself would give {}",
                               c.effect.name, parameters.empty() ? "" : " (", parameters, parameters.empty() ? "" : ")",
                               coefficient, traits.regressor_is_error ? "1" : "a positive one (" + traits.positive_because + ")"));
  return true;
}

// Among the candidates within 0.1 % of the best held-out MSE, the one with the lowest in-sample
// BIC = N ln(SSE/N) + k ln N.
std::size_t PickByBic(const RegressorMatrix& m, const BlockGrams& grams, const std::vector<Eigen::Index>& selected,
                      const std::vector<double>& mse, const std::vector<bool>& used, double best_mse) {
  const double log_n = std::log(grams.n());
  std::size_t pick = m.cands.size();
  double best_bic = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < m.cands.size(); ++c) {
    if (used[c] || mse[c] > best_mse * (1.0 + kHeldOutTie)) continue;
    std::vector<Eigen::Index> trial = selected;
    trial.insert(trial.end(), m.cands[c].idx.begin(), m.cands[c].idx.end());
    double sse = 0.0;
    grams.Fit(trial, &sse);
    const double bic = grams.n() * std::log(std::max(sse, 1e-300) / grams.n()) + static_cast<double>(trial.size()) * log_n;
    if (bic < best_bic) { best_bic = bic; pick = c; }
  }
  return pick;
}

// Does pair `a` hold pair `b` (the same multiplier, b's modulator 1 or one of a's nested modulators)?
bool Holds(const EffectType& a, const EffectType& b) {
  if (a.multiplier.empty() || a.multiplier != b.multiplier) return false;
  if (b.modulator == "constant") return a.traits.nests_constant_pair;
  return std::find(a.traits.nested_modulators.begin(), a.traits.nested_modulators.end(), b.modulator) !=
         a.traits.nested_modulators.end();
}

// The rivals of `pick` in this round (Selection::rivals): the candidates not `used` (chosen, set aside or implausible)
// whose held-out MSE is within kRivalMargin above its own and which have a shape parameter to refine; not for a law,
// and not a pair that holds the pick or that the pick holds (NestedUnlessSignificant settled those by significance).
void RecordRivals(const RegressorMatrix& m, const std::vector<double>& mse, const std::vector<bool>& used,
                  std::size_t pick, Selection* s) {
  const EffectType& chosen = *m.cands[pick].type;
  if (chosen.traits.friction_law_replacement) return;
  std::vector<std::size_t> near;
  for (std::size_t c = 0; c < m.cands.size(); ++c) {
    const EffectType& type = *m.cands[c].type;
    if (c == pick || used[c] || !std::isfinite(mse[c]) || type.traits.refined_parameter.empty() ||
        type.traits.friction_law_replacement || m.cands[c].effect.name == m.cands[pick].effect.name ||
        Holds(type, chosen) || Holds(chosen, type)) {
      continue;
    }
    if (mse[c] <= (1.0 + kRivalMargin) * mse[pick]) near.push_back(c);
  }
  std::sort(near.begin(), near.end(), [&](std::size_t a, std::size_t b) { return mse[a] < mse[b]; });
  if (near.size() > kMaxRivals) near.resize(kMaxRivals);
  for (std::size_t c : near) s->rivals.emplace_back(s->order.size(), m.cands[c].effect);
}

// The held-out MSE of every candidate not `used` added to `selected` (infinity for the used ones; a candidate whose
// coefficient is implausible is marked used).
std::vector<double> TrialErrors(const RegressorMatrix& m, const BlockGrams& grams, const std::vector<Eigen::Index>& selected,
                                std::vector<bool>* used, std::vector<std::string>* notes) {
  std::vector<double> mse(m.cands.size(), std::numeric_limits<double>::infinity());
  for (std::size_t c = 0; c < m.cands.size(); ++c) {
    if ((*used)[c]) continue;
    std::vector<Eigen::Index> trial = selected;
    trial.insert(trial.end(), m.cands[c].idx.begin(), m.cands[c].idx.end());
    if (ImplausibleCoefficient(m.cands[c], m, grams, trial, notes)) {
      (*used)[c] = true;  // never chosen; not in `order`
      continue;
    }
    mse[c] = grams.HeldOutMse(trial);
  }
  return mse;
}

// The family a candidate's significance is family-wise over: the search's candidates for a pair the grammar's search
// proposed (EffectType::searched; at least Selection::family, the search's size before any retry), else 1.
std::size_t FamilyOf(const RegressorMatrix& m, const Selection& s, const EffectType& type) {
  return type.searched ? std::max(s.family, SearchedCount(m)) : 1;
}

// The candidate that `pick` nests (EffectTraits::nests_constant_pair: its multiplier × 1; ::nested_modulators: its
// multiplier × a modulator whose shape is a limit of its own) with the lowest held-out error, when it is among the
// candidates, not used, worth choosing itself (its held-out gain over `s.mse_last` reaches min_gain), and `pick`'s gain
// over it is not significant at `pick`'s own bar (FamilyOf); else `pick`.
std::size_t NestedUnlessSignificant(const RegressorMatrix& m, const BlockGrams& grams, const DiagnosisOptions& options,
                                    const Selection& s, const std::vector<bool>& used, const std::vector<double>& mse,
                                    std::size_t pick, std::vector<std::string>* notes) {
  const std::vector<Eigen::Index>& selected = s.selected;
  const double mse_last = s.mse_last;
  const EffectType& type = *m.cands[pick].type;
  if (!(options.significance_t > 0.0) || type.multiplier.empty()) return pick;
  std::vector<std::string> modulators = type.traits.nested_modulators;
  if (type.traits.nests_constant_pair) modulators.emplace_back("constant");
  std::vector<std::string> nested;
  for (const std::string& modulator : modulators) {
    if (const EffectType* pair = EffectRegistry::Global().FindPair(type.multiplier, modulator)) nested.push_back(pair->name);
  }
  std::size_t best = m.cands.size();
  for (std::size_t c = 0; c < m.cands.size(); ++c) {
    if (used[c] || !std::isfinite(mse[c]) || c == pick) continue;
    if (std::find(nested.begin(), nested.end(), m.cands[c].effect.name) == nested.end()) continue;
    if (best == m.cands.size() || mse[c] < mse[best]) best = c;
  }
  if (best == m.cands.size() || !(mse_last > 0.0) || 1.0 - mse[best] / mse_last < options.min_gain) return pick;
  std::vector<Eigen::Index> smaller = selected, larger = selected;
  smaller.insert(smaller.end(), m.cands[best].idx.begin(), m.cands[best].idx.end());
  larger.insert(larger.end(), m.cands[pick].idx.begin(), m.cands[pick].idx.end());
  // The modulation a searched pair adds to the one it holds was found by the same search (its shape scanned on the
  // record), so it must pass the same family-wise bar as a searched pair added on its own: with the nested pair in
  // the model first, the larger one would be a new candidate of that search.
  const std::size_t family = FamilyOf(m, s, type);
  const double needed = FamilyWiseT(options.significance_t, family);
  const std::string among = type.searched ? fmt::format(", its shape one of {} pairs searched", family) : "";
  const double t = GainSignificance(m, grams, smaller, larger, options.significance_batches);
  if (t >= needed) {
    notes->push_back(fmt::format("{} chosen over {}, whose shape it holds: its held-out gain over it is significant "
                                 "(Diebold–Mariano t = {:.2f} ≥ {:.2f}{})",
                                 m.cands[pick].effect.name, m.cands[best].effect.name, t, needed, among));
    return pick;
  }
  notes->push_back(fmt::format("{} not chosen over {}, whose shape it holds: its held-out gain over it is not "
                               "significant (Diebold–Mariano t = {:.2f} < {:.2f}{})",
                               m.cands[pick].effect.name, m.cands[best].effect.name, t, needed, among));
  return best;
}

}  // namespace

double FamilyWiseT(double t_single, std::size_t candidates) {
  if (candidates <= 1) return t_single;
  const boost::math::normal normal;
  const double p = boost::math::cdf(boost::math::complement(normal, t_single));
  return boost::math::quantile(boost::math::complement(normal, p / static_cast<double>(candidates)));
}

std::size_t SearchedCount(const RegressorMatrix& m) {
  return static_cast<std::size_t>(
      std::count_if(m.cands.begin(), m.cands.end(), [](const Candidate& c) { return c.type->searched; }));
}

Selection StartSelection(const BlockGrams& grams, Eigen::Index p) {
  Selection s;
  for (Eigen::Index j = 0; j < p; ++j) s.selected.push_back(j);
  s.mse_base = s.mse_last = grams.HeldOutMse(s.selected);
  return s;
}

Selection SelectInOrder(const RegressorMatrix& m, const BlockGrams& grams, Eigen::Index p, std::size_t count) {
  Selection s = StartSelection(grams, p);
  for (std::size_t i = 0; i < count; ++i) {
    s.selected.insert(s.selected.end(), m.cands[i].idx.begin(), m.cands[i].idx.end());
    const double mse = grams.HeldOutMse(s.selected);
    s.order.push_back(i);
    s.scores.push_back(s.mse_last > 0.0 ? 1.0 - mse / s.mse_last : 0.0);
    s.cumulative.push_back(s.mse_base > 0.0 ? 1.0 - mse / s.mse_base : 0.0);
    s.mse_last = mse;
  }
  return s;
}

double GainSignificance(const RegressorMatrix& m, const BlockGrams& grams, const std::vector<Eigen::Index>& selected,
                        const std::vector<Eigen::Index>& trial, Eigen::Index batches) {
  return LossDifferenceT(grams.HeldOutErrors(selected, m), grams.HeldOutErrors(trial, m), batches);
}

Eigen::VectorXd BatchMeans(const Eigen::VectorXd& x, Eigen::Index batches) {
  const Eigen::Index n = x.size();
  batches = std::clamp<Eigen::Index>(batches, 2, std::max<Eigen::Index>(2, n / 8));
  Eigen::VectorXd means(batches);
  for (Eigen::Index b = 0; b < batches; ++b) {
    const Eigen::Index lo = b * n / batches, hi = (b + 1) * n / batches;
    means(b) = x.segment(lo, hi - lo).mean();
  }
  return means;
}

double LossDifferenceT(const Eigen::VectorXd& before, const Eigen::VectorXd& after, Eigen::Index batches) {
  const Eigen::VectorXd means = BatchMeans(before.array().square() - after.array().square(), batches);
  const double mean = means.mean();
  const double var = (means.array() - mean).square().sum() / static_cast<double>(means.size() - 1);
  const double se = std::sqrt(var / static_cast<double>(means.size()));
  return se > 0.0 ? mean / se : (mean > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
}

bool AddBestEffect(const RegressorMatrix& m, const BlockGrams& grams, const DiagnosisOptions& options,
                   std::vector<bool>* used, Selection* s, std::vector<std::string>* notes) {
  const std::vector<double> mse = TrialErrors(m, grams, s->selected, used, notes);
  for (;;) {
    double best_mse = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < m.cands.size(); ++c) {
      if (!(*used)[c]) best_mse = std::min(best_mse, mse[c]);
    }
    if (!std::isfinite(best_mse)) return false;
    // Down the nesting while the larger pair does not beat the smaller one significantly (a window, then the step it
    // holds, then the multiplier × 1).
    std::size_t pick = PickByBic(m, grams, s->selected, mse, *used, best_mse);
    for (std::size_t larger = m.cands.size(); pick != larger;) {
      larger = pick;
      pick = NestedUnlessSignificant(m, grams, options, *s, *used, mse, larger, notes);
    }
    const double gain = s->mse_last > 0.0 ? 1.0 - mse[pick] / s->mse_last : 0.0;
    if (!(gain >= options.min_gain) || gain <= 0.0) return false;
    std::vector<Eigen::Index> trial = s->selected;
    trial.insert(trial.end(), m.cands[pick].idx.begin(), m.cands[pick].idx.end());
    (*used)[pick] = true;
    if (mse[pick] < s->leak_mse) {
      notes->push_back(fmt::format(
          "{} refused: its held-out error ({:.3g}) would fall below {:g} × the record's white noise floor ({:.3g}); no model "
          "can do better than the noise, so the candidate fits the measurement's own noise (a regressor built from the "
          "compared output leaks it), not physics",
          m.cands[pick].effect.name, std::sqrt(mse[pick]), options.leak_floor_ratio,
          std::sqrt(s->leak_mse) / options.leak_floor_ratio));
      continue;
    }
    // The floor's mean square, from the leak check's threshold (leak_floor_ratio × the floor, squared).
    const double floor_mse =
        options.leak_floor_ratio > 0.0 ? s->leak_mse / (options.leak_floor_ratio * options.leak_floor_ratio) : 0.0;
    const double relevant_mse = floor_mse * options.relevance_floor_ratio * options.relevance_floor_ratio;
    if (s->mse_last - mse[pick] < relevant_mse) {
      notes->push_back(fmt::format(
          "{} not named: it lowers the held-out error by an RMS of {:.3g}, {:.2f} × the record's white noise floor "
          "({:.3g}), under {:g} ×: without it the model stays within {:.2g} × the floor, and the record cannot show it "
          "above its noise",
          m.cands[pick].effect.name, std::sqrt(std::max(0.0, s->mse_last - mse[pick])),
          std::sqrt(std::max(0.0, s->mse_last - mse[pick]) / floor_mse), std::sqrt(floor_mse),
          options.relevance_floor_ratio,
          std::sqrt(1.0 + options.relevance_floor_ratio * options.relevance_floor_ratio)));
      s->set_aside.push_back(pick);
      continue;
    }
    if (options.significance_t > 0.0 && gain < options.significance_exempt_gain) {
      const double t = GainSignificance(m, grams, s->selected, trial, options.significance_batches);
      const bool searched = m.cands[pick].type->searched;
      const std::size_t family = FamilyOf(m, *s, *m.cands[pick].type);
      const double needed = FamilyWiseT(options.significance_t, family);
      if (t < needed) {
        notes->push_back(fmt::format(
            "{} not chosen: its held-out gain ({:.1f} %) is not significant against the residual's autocorrelation "
            "(Diebold–Mariano t = {:.2f} < {:.2f} over {} batches{})",
            m.cands[pick].effect.name, 100.0 * gain, t, needed, options.significance_batches,
            searched ? fmt::format(", one of {} pairs searched", family) : ""));
        s->set_aside.push_back(pick);
        continue;
      }
    }
    RecordRivals(m, mse, *used, pick, s);
    s->order.push_back(pick);
    s->selected = std::move(trial);
    s->scores.push_back(gain);
    s->cumulative.push_back(s->mse_base > 0.0 ? 1.0 - mse[pick] / s->mse_base : 0.0);
    s->mse_last = mse[pick];
    return true;
  }
}

void SelectEffects(const RegressorMatrix& m, const BlockGrams& grams, std::vector<bool> used,
                   const DiagnosisOptions& options, Selection* s, std::vector<std::string>* notes) {
  while (static_cast<Eigen::Index>(s->order.size()) < options.max_effects) {
    if (!AddBestEffect(m, grams, options, &used, s, notes)) break;
  }
}

bool AddFrictionLaw(const RegressorMatrix& m, const BlockGrams& grams, const Selection& chosen,
                    const DiagnosisOptions& options, LawSearch* law, std::vector<std::string>* notes) {
  const std::size_t l = law->effects.size();
  if (l >= 3) return false;
  std::vector<bool> used(m.cands.size());
  for (std::size_t c = 0; c < m.cands.size(); ++c) {
    bool taken = c < l;
    for (const auto& e : law->effects) taken = taken || e.name == m.cands[c].effect.name;
    used[c] = taken || !m.cands[c].type->traits.friction_law_replacement;
  }
  Selection trial = chosen;
  if (!AddBestEffect(m, grams, options, &used, &trial, notes)) return false;
  const Candidate& c = m.cands[trial.order.back()];
  law->effects.push_back(c.effect);
  law->scores.push_back(trial.scores.back());
  law->cumulative.push_back(trial.cumulative.back());
  const Eigen::Index k = law->columns.cols(), kc = static_cast<Eigen::Index>(c.idx.size());
  law->columns.conservativeResize(Eigen::NoChange, k + kc);
  for (Eigen::Index j = 0; j < kc; ++j) {
    const Eigen::Index col = c.idx[static_cast<std::size_t>(j)];
    law->columns.col(k + j) = m.Col(col) * m.scale(col);
  }
  return true;
}

}  // namespace mb::diagnosis_detail
