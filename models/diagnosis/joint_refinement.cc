// Joint refinement (DiagnoseMissingEffects, steps 3c–3d). Each chosen effect's nonlinear parameter
// (EffectTraits::refined_parameter) was estimated in what the effects chosen before it left, without those found after
// it: it is re-estimated by coordinate passes over the parameters, each a scan (log grid, then golden section) of the
// weighted residual sum of squares of the joint fit with the base and every other chosen effect in, the Huber weights
// refit (IRLS) before each pass; the friction-law replacements first, since they change ŷ and with it the columns built
// from ŷ. When a parameter moved, the ranking is rebuilt on the refined effects and their scores recomputed; the
// candidates set aside as insignificant whose parameter may be corrected are then tried again, each refined jointly
// with the chosen effects. Source: DIAGNOSIS.md, "Naming the missing effect", step 1 (the final numbers from a joint
// refit) and "When the base model is wrong elsewhere" (the friction law first); docs/diagnosis.md, "Ranking".
#include "models/diagnosis/joint_refinement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/robust_weighting.h"

namespace mb::diagnosis_detail {

JointRefinement::JointRefinement(const DiagnosisSignals& signals, const Eigen::MatrixXd& base,
                                 const Eigen::VectorXd& weights, const DiagnosisOptions& options,
                                 std::vector<EffectInstance> effects, std::size_t laws)
    : signals_(signals), corrected_(signals), base_(base), options_(options), effects_(std::move(effects)), laws_(laws) {
  weights_ = weights;
  base_norm_ = base.colwise().norm().transpose();
  Weigh();
  columns_.resize(effects_.size());
  Rebuild(kAll);
}

DiagnosisSignals JointRefinement::corrected() const {
  DiagnosisSignals out = corrected_;
  out.command_with.clear();
  return out;
}

bool JointRefinement::MultipliesTheCommand(std::size_t i) const {
  const EffectType& type = LookupEffect(effects_[i].name);
  const MultiplierRow* row = FindMultiplier(type.multiplier);
  return row != nullptr && row->model_force && type.modulator != "constant";
}

Eigen::MatrixXd JointRefinement::Design() const {
  Eigen::Index k = base_.cols();
  for (const auto& c : columns_) k += c.cols();
  Eigen::MatrixXd x(signals_.size(), k);
  x.leftCols(base_.cols()) = base_;
  Eigen::Index col = base_.cols();
  for (const auto& c : columns_) {
    x.middleCols(col, c.cols()) = c;
    col += c.cols();
  }
  return x;
}

void JointRefinement::Run(int sweeps) {
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    Reweigh();
    bool moved = false;
    for (std::size_t j = 0; j < effects_.size(); ++j) moved = RefineOne(j) || moved;
    if (!moved) break;
  }
}

Eigen::MatrixXd JointRefinement::ColumnsOf(const EffectInstance& effect) const {
  const EffectType& type = LookupEffect(effect.name);
  Eigen::MatrixXd columns = type.regressors(effect, corrected_).columns;
  FilterCandidateColumns(type, corrected_, options_, &columns);
  return columns;
}

void JointRefinement::Rebuild(std::size_t j) {
  const bool law_changed = j == kAll || j < laws_;
  for (std::size_t i = 0; i < laws_; ++i) {
    if (j == kAll || i == j) columns_[i] = Columns(i);
  }
  if (law_changed) Correct();
  for (std::size_t i = laws_; i < effects_.size(); ++i) {
    const bool from_output = LookupEffect(effects_[i].name).traits.regressor_in_output_band;
    if (j == kAll || i == j || (law_changed && from_output)) columns_[i] = Columns(i);
  }
}

void JointRefinement::Correct() {
  const Eigen::Index n = signals_.size();
  if (signals_.model_output.size() != n) return;
  const Eigen::Index p = base_.cols();
  Eigen::Index kl = 0;
  for (std::size_t i = 0; i < laws_; ++i) kl += columns_[i].cols();
  // The laws' columns weighted; the base's weighted Gram and moment are the sweep's (Weigh).
  Eigen::MatrixXd wl(n, kl);
  Eigen::VectorXd norm(p + kl);
  norm.head(p) = base_norm_;
  Eigen::Index c = 0;
  for (std::size_t i = 0; i < laws_; c += columns_[i].cols(), ++i) {
    wl.middleCols(c, columns_[i].cols()) = sw_.asDiagonal() * columns_[i];
    norm.segment(p + c, columns_[i].cols()) = columns_[i].colwise().norm().transpose();
  }
  Eigen::MatrixXd g(p + kl, p + kl);
  g.topLeftCorner(p, p) = base_wgram_;
  g.topRightCorner(p, kl) = wbase_.transpose() * wl;
  g.bottomLeftCorner(kl, p) = g.topRightCorner(p, kl).transpose();
  g.bottomRightCorner(kl, kl) = wl.transpose() * wl;
  Eigen::VectorXd h(p + kl);
  h << base_wmoment_, wl.transpose() * wr_;
  // Columns scaled to unit norm (unweighted), a ridge of 1e-10 on the scaled normal equations.
  const Eigen::VectorXd scale = (norm.array() + 1e-300).inverse();
  g = scale.asDiagonal() * g * scale.asDiagonal();
  g.diagonal().array() += 1e-10;
  const Eigen::VectorXd coef = scale.cwiseProduct(g.ldlt().solve(scale.cwiseProduct(h)));
  corrected_.model_output = signals_.model_output + base_ * coef.head(p);
  Eigen::Index col = p;
  for (std::size_t i = 0; i < laws_; col += columns_[i].cols(), ++i) {
    corrected_.model_output += columns_[i] * coef.segment(col, columns_[i].cols());
  }
}

void JointRefinement::Weigh() {
  sw_ = weights_.cwiseSqrt();
  wbase_ = sw_.asDiagonal() * base_;
  wr_ = sw_.cwiseProduct(signals_.residual);
  base_wgram_ = wbase_.transpose() * wbase_;
  base_wmoment_ = wbase_.transpose() * wr_;
}

void JointRefinement::Reweigh() {
  Eigen::VectorXd rest;
  weights_ = RobustWeights(Design(), signals_.residual, options_.huber_k, &rest);
  Weigh();
  Rebuild(kAll);
  PredictCommands();  // a fixed point over the passes
}

void JointRefinement::PredictCommands() {
  std::vector<std::size_t> of_command;
  for (std::size_t i = laws_; i < effects_.size(); ++i) {
    if (MultipliesTheCommand(i)) of_command.push_back(i);
  }
  if (of_command.empty() || signals_.drive_force.size() != 0 || signals_.model_output.size() != signals_.size()) return;
  // The weighted least-squares fit of the residual on [base, every effect's columns] (scaled to unit norm, a ridge of
  // 1e-10), and each pair's own part of it on ŷ as the base's refit and the laws correct it.
  const Eigen::MatrixXd x = Design();
  const Eigen::MatrixXd wx = sw_.asDiagonal() * x;
  const Eigen::VectorXd scale = (wx.colwise().norm().transpose().array() + 1e-300).inverse();
  Eigen::MatrixXd g = scale.asDiagonal() * (wx.transpose() * wx) * scale.asDiagonal();
  g.diagonal().array() += 1e-10;
  const Eigen::VectorXd coef = scale.cwiseProduct(g.ldlt().solve(scale.cwiseProduct(wx.transpose() * wr_)));
  std::vector<Eigen::Index> first(effects_.size());
  Eigen::Index col = base_.cols();
  for (std::size_t i = 0; i < effects_.size(); col += columns_[i].cols(), ++i) first[i] = col;
  corrected_.command_with.clear();
  for (std::size_t i : of_command) {
    const Eigen::VectorXd own = columns_[i] * coef.segment(first[i], columns_[i].cols());
    auto [it, inserted] = corrected_.command_with.try_emplace(effects_[i].name, corrected_.model_output + own);
    if (!inserted) it->second += own;  // two of the same pair: both act on the drive's force
  }
  for (std::size_t i : of_command) columns_[i] = Columns(i);
}

bool JointRefinement::Varies(std::size_t i, std::size_t j) const {
  return i == j || (j < laws_ && i >= laws_ && LookupEffect(effects_[i].name).traits.regressor_in_output_band);
}

JointRefinement::FixedPart JointRefinement::Fix(std::size_t j) const {
  FixedPart f;
  f.response = wr_;
  Eigen::Index k = wbase_.cols();
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (!Varies(i, j) && !LookupEffect(effects_[i].name).traits.regressor_is_error) k += columns_[i].cols();
  }
  f.x.resize(wbase_.rows(), k);
  f.x.leftCols(wbase_.cols()) = wbase_;
  Eigen::Index col = wbase_.cols();
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (Varies(i, j)) continue;
    if (LookupEffect(effects_[i].name).traits.regressor_is_error) {
      f.response -= sw_.cwiseProduct(columns_[i].rowwise().sum());
      continue;
    }
    f.x.middleCols(col, columns_[i].cols()) = sw_.asDiagonal() * columns_[i];
    col += columns_[i].cols();
  }
  f.gram = f.x.transpose() * f.x;
  f.moment = f.x.transpose() * f.response;
  f.response_squared = f.response.squaredNorm();
  return f;
}

double JointRefinement::Sse(const FixedPart& f, std::size_t j, const Eigen::MatrixXd* own_columns) const {
  const auto column = [&](std::size_t i) -> const Eigen::MatrixXd& {
    return own_columns && i == j ? *own_columns : columns_[i];
  };
  // The response changes only with a varying effect whose regressor is the error: else the fixed part's moment holds.
  Eigen::VectorXd own;
  const Eigen::VectorXd* response = &f.response;
  Eigen::Index kv = 0;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (!Varies(i, j)) continue;
    if (!LookupEffect(effects_[i].name).traits.regressor_is_error) {
      kv += column(i).cols();
    } else if (response == &f.response) {
      own = f.response;
      response = &own;
    }
  }
  // The varying columns, weighted: one scratch per thread, kept between the trials of a scan (the same shape each time)
  // rather than an N-row block mapped anew for each trial under AddressSanitizer (ZeroPhaseLowPassColumns, alike).
  thread_local Eigen::MatrixXd xv;
  xv.resize(wbase_.rows(), kv);
  Eigen::Index col = 0;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (!Varies(i, j)) continue;
    if (LookupEffect(effects_[i].name).traits.regressor_is_error) {
      own -= sw_.cwiseProduct(column(i).rowwise().sum());
      continue;
    }
    xv.middleCols(col, column(i).cols()) = sw_.asDiagonal() * column(i);
    col += column(i).cols();
  }
  const Eigen::Index kf = f.x.cols(), k = kf + kv;
  Eigen::MatrixXd g(k, k);
  g.topLeftCorner(kf, kf) = f.gram;
  g.topRightCorner(kf, kv) = f.x.transpose() * xv;
  g.bottomLeftCorner(kv, kf) = g.topRightCorner(kf, kv).transpose();
  g.bottomRightCorner(kv, kv) = xv.transpose() * xv;
  Eigen::VectorXd h(k);
  if (response == &f.response) {
    h << f.moment, xv.transpose() * f.response;
  } else {
    h << f.x.transpose() * own, xv.transpose() * own;
  }
  const Eigen::VectorXd d = (g.diagonal().array() > 0.0).select(g.diagonal().array().rsqrt(), 1.0);
  g = d.asDiagonal() * g * d.asDiagonal();
  g.diagonal().array() += 1e-10;
  h = d.cwiseProduct(h);
  const double response_squared = response == &f.response ? f.response_squared : own.squaredNorm();
  return std::max(0.0, response_squared - h.dot(g.ldlt().solve(h)));
}

bool JointRefinement::RefineOne(std::size_t j) {
  const EffectTraits& traits = LookupEffect(effects_[j].name).traits;
  const auto it = effects_[j].parameters.find(traits.refined_parameter);
  if (traits.refined_parameter.empty() || it == effects_[j].parameters.end()) return false;
  const double start = it->second, sign = start < 0.0 ? -1.0 : 1.0, magnitude = std::abs(start);
  if (!(magnitude > 0.0) || !(traits.refinement_range > 1.0)) return false;
  const FixedPart fixed = Fix(j);
  const auto sse = [&](double value) {
    effects_[j].parameters[traits.refined_parameter] = sign * value;
    try {
      Rebuild(j);
    } catch (const std::invalid_argument&) {
      return std::numeric_limits<double>::infinity();
    }
    return Sse(fixed, j);
  };
  // When only its own columns vary (an effect after the laws; a law when no chosen effect's columns are built from ŷ),
  // a trial need not touch the state: the same sum of squares from the trial's own columns (a law's ŷ correction
  // enters no column then), the grid's values tried in parallel (MinimiseOnLogGrid), the state set after.
  bool own_only = true;
  for (std::size_t i = 0; i < effects_.size(); ++i) own_only = own_only && (i == j || !Varies(i, j));
  const auto trial_sse = [&](double value) {
    EffectInstance trial = effects_[j];
    trial.parameters[traits.refined_parameter] = sign * value;
    Eigen::MatrixXd columns;
    try {
      columns = ColumnsOf(trial);
    } catch (const std::invalid_argument&) {
      return std::numeric_limits<double>::infinity();
    }
    return Sse(fixed, j, &columns);
  };
  const double before = sse(magnitude);
  // A log grid of ratio 1.6 (7 points over a factor 4 either way), then 12 golden-section steps (to 0.3 %).
  const int grid = std::max(5, static_cast<int>(std::ceil(2.0 * std::log(traits.refinement_range) / std::log(1.6))) + 1);
  const double bound = traits.refined_upper_bound ? traits.refined_upper_bound(corrected_) : 0.0;
  const double hi = bound > 0.0 ? std::min(magnitude * traits.refinement_range, bound)
                                : magnitude * traits.refinement_range;
  const double lo = std::min(magnitude, hi) / traits.refinement_range;
  if (!(hi > lo)) return false;
  const double found = own_only ? MinimiseOnLogGrid(lo, hi, grid, 12, trial_sse, true)
                                : MinimiseOnLogGrid(lo, hi, grid, 12, sse);
  const double after = sse(found);
  if (after < before && std::abs(found / magnitude - 1.0) > 1e-3) return true;
  sse(magnitude);  // back to the start
  return false;
}

void KeepChosenOnly(Ranking* ranking) {
  RegressorMatrix& m = ranking->m;
  Selection& s = ranking->chosen;
  std::vector<Eigen::Index> columns;
  for (Eigen::Index j = 0; j < m.base.cols(); ++j) columns.push_back(j);
  for (std::size_t c : s.order) columns.insert(columns.end(), m.cands[c].idx.begin(), m.cands[c].idx.end());
  if (columns != s.selected || !ranking->grams) return;  // not the selection's layout: keep everything
  ranking->grams = ranking->grams->Restrict(s.selected);  // first: lazy Grams read m's columns
  RegressorMatrix kept;
  kept.base = std::move(m.base);
  kept.sw = std::move(m.sw);
  kept.wr = std::move(m.wr);
  Eigen::Index col = kept.base.cols();
  for (std::size_t c : s.order) {
    Candidate candidate = std::move(m.cands[c]);
    for (Eigen::Index& j : candidate.idx) j = col++;
    kept.cands.push_back(std::move(candidate));
  }
  kept.scale.resize(col);
  for (Eigen::Index j = 0; j < col; ++j) kept.scale(j) = m.scale(s.selected[static_cast<std::size_t>(j)]);
  kept.IndexColumns();
  for (Eigen::Index j = 0; j < col; ++j) s.selected[static_cast<std::size_t>(j)] = j;
  for (std::size_t i = 0; i < s.order.size(); ++i) s.order[i] = i;
  s.set_aside.clear();
  m = std::move(kept);
}

std::vector<EffectInstance> ChosenInstances(const Ranking& ranking) {
  std::vector<EffectInstance> chosen;
  for (std::size_t c : ranking.chosen.order) chosen.push_back(ranking.m.cands[c].effect);
  return chosen;
}

void InstallRefined(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
                    std::size_t laws, const Eigen::VectorXd& weights, RegressorMatrix m, Selection s, Ranking* out) {
  s.family = std::max({s.family, out->chosen.family, SearchedCount(out->m)});  // the search's, not the refit's few
  out->law_columns = base_cols;
  for (std::size_t i = 0; i < laws; ++i) {
    const Eigen::Index k = out->law_columns.cols(), kc = static_cast<Eigen::Index>(m.cands[i].idx.size());
    out->law_columns.conservativeResize(Eigen::NoChange, k + kc);
    for (Eigen::Index j = 0; j < kc; ++j) {
      const Eigen::Index col = m.cands[i].idx[static_cast<std::size_t>(j)];
      out->law_columns.col(k + j) = m.Col(col) * m.scale(col);
    }
  }
  RobustWeights(out->law_columns, signals.residual, options.huber_k, &out->law_residual);
  out->weights = weights;
  out->m = std::move(m);
  out->grams.emplace(out->m, options.folds);
  const double leak_mse = out->chosen.leak_mse;
  out->chosen = std::move(s);
  out->chosen.leak_mse = leak_mse;
}

void RefineChosenEffects(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                         const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                         std::vector<std::string>* notes) {
  if (options.refinement_sweeps <= 0 || out->chosen.order.empty()) return;
  const std::vector<EffectInstance> chosen = ChosenInstances(*out);
  JointRefinement refinement(signals, base_cols, out->weights, options, chosen, laws);
  refinement.Run(options.refinement_sweeps);
  std::vector<std::string> moved;
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    const std::string& name = LookupEffect(chosen[i].name).traits.refined_parameter;
    if (name.empty() || !chosen[i].parameters.count(name)) continue;
    const double before = chosen[i].parameters.at(name), after = refinement.effects()[i].parameters.at(name);
    if (after == before) continue;
    moved.push_back(fmt::format("{}'s {} re-estimated in the joint fit with every chosen effect in: {:.4g} → {:.4g}",
                                chosen[i].name, name, before, after));
  }
  if (moved.empty()) return;
  std::vector<std::string> build_notes;
  RegressorMatrix m = BuildCandidateMatrix(refinement.corrected(), base_cols, refinement.effects(), options, &build_notes);
  if (m.cands.size() != chosen.size()) return;  // a refined effect the base spans now: keep the ranking's
  m.Weigh(signals.residual, refinement.weights());
  const BlockGrams grams(m, options.folds);
  Selection s = SelectInOrder(m, grams, base_cols.cols(), m.cands.size());
  InstallRefined(signals, base_cols, options, laws, refinement.weights(), std::move(m), std::move(s), out);
  notes->insert(notes->end(), moved.begin(), moved.end());
}

std::vector<EffectInstance> SetAsideForRetry(const Ranking& ranking) {
  std::vector<EffectInstance> retry;
  for (std::size_t c : ranking.chosen.set_aside) {
    const EffectTraits& traits = ranking.m.cands[c].type->traits;
    if (!traits.refined_parameter.empty() && !traits.friction_law_replacement) retry.push_back(ranking.m.cands[c].effect);
  }
  return retry;
}

void RetrySetAside(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
                   std::size_t laws, const std::vector<EffectInstance>& retry, Ranking* out,
                   std::vector<std::string>* notes) {
  if (options.refinement_sweeps <= 0) return;
  // Set aside as insignificant, a candidate must pass that test now, whatever its gain: its gain is measured under the
  // refinement's robust weights, refit with it in, which can down-weight the very samples that showed it to be noise
  // (a noise-only record's force-constant ripple: 2.5 % under the ranking's weights, 31.9 % under the retry's).
  DiagnosisOptions tested = options;
  tested.significance_exempt_gain = std::numeric_limits<double>::infinity();
  for (const EffectInstance& candidate : retry) {
    if (static_cast<Eigen::Index>(out->chosen.order.size()) >= options.max_effects) return;
    std::vector<EffectInstance> trial = ChosenInstances(*out);
    trial.push_back(candidate);
    JointRefinement refinement(signals, base_cols, out->weights, options, trial, laws);
    refinement.Run(options.refinement_sweeps);
    std::vector<std::string> trial_notes;
    RegressorMatrix m = BuildCandidateMatrix(refinement.corrected(), base_cols, refinement.effects(), options, &trial_notes);
    if (m.cands.size() != trial.size()) continue;
    m.Weigh(signals.residual, refinement.weights());
    const BlockGrams grams(m, options.folds);
    Selection s = SelectInOrder(m, grams, base_cols.cols(), m.cands.size() - 1);
    s.leak_mse = out->chosen.leak_mse;
    s.family = std::max(out->chosen.family, SearchedCount(out->m));
    std::vector<bool> used(m.cands.size(), true);
    used.back() = false;
    const bool chosen = AddBestEffect(m, grams, tested, &used, &s, &trial_notes);
    const std::string& parameter = m.cands.back().type->traits.refined_parameter;
    const std::string refit = fmt::format("{} tried again with its {} re-estimated jointly with the chosen effects ({:.4g} "
                                          "→ {:.4g})", candidate.name, parameter, candidate.parameters.at(parameter),
                                          m.cands.back().effect.parameters.at(parameter));
    if (!chosen) {
      notes->push_back(refit + ": not chosen" + (trial_notes.empty() ? "" : " (" + trial_notes.back() + ")"));
      continue;
    }
    // Its gain is over the others refit jointly with it; it must beat the ranking as it stands too, else the gain came
    // from moving the others' parameters (a law's v_c walked off to make room), not from the candidate.
    if (!(s.mse_last <= (1.0 - options.min_gain) * out->chosen.mse_last)) {
      notes->push_back(fmt::format("{}: not chosen (held-out MSE {:.4g} against {:.4g} for the effects chosen without "
                                   "it: its gain came from re-estimating the others)",
                                   refit, s.mse_last, out->chosen.mse_last));
      continue;
    }
    notes->push_back(fmt::format("{}: chosen, held-out gain {:.1f} %", refit, 100.0 * s.scores.back()));
    InstallRefined(signals, base_cols, options, laws, refinement.weights(), std::move(m), std::move(s), out);
  }
}

}  // namespace mb::diagnosis_detail
