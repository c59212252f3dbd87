#pragma once
// What a residual depends on (DIAGNOSIS.md, "When nothing is linear enough"; issue 40, item 4): the held-out share of
// the residual that a smooth function of one signal alone explains, for every signal the record holds — the position,
// the velocity, the direction of travel, the acceleration, the model's force, the time and every log column the diagram
// does not read. Additive components in the Automatic Statistician's sense (Duvenaud et al. 2013; Lloyd et al. 2014),
// each a piecewise-linear function (hat functions on knots at the signal's quantiles), scored on contiguous held-out
// blocks: "the residual depends on position and the direction of travel; not on time". The honest answer when no
// catalogue or grammar term fits.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/effect_catalogue.h"

namespace mb {

struct SignalRelevance {
  std::string signal;          ///< "position", "velocity", "direction of travel", "acceleration", "model force",
                               ///< "time", or a log column's name
  double heldout_share = 0.0;  ///< 1 − held-out MSE of f(signal)/held-out MSE of a constant, clamped at 0
};

/// The relevance of each signal of `signals` to `residual` (N), most relevant first. `folds` contiguous blocks
/// (>= 2), `knots` hat functions per signal (>= 2). A signal that does not vary is left out; the model force only when
/// DiagnosisSignals::model_output is present (never the logged command: the compared output itself).
/// Throws std::invalid_argument when the residual's length differs from the signals'.
std::vector<SignalRelevance> RankSignalRelevance(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                                 Eigen::Index folds = 5, Eigen::Index knots = 12);

/// The ranking in words: "depends on position (41.2 %), direction of travel (12.0 %); not on time (0.1 %), …", a signal
/// counted as a dependence from `min_share` of the held-out residual on.
std::string DescribeRelevance(const std::vector<SignalRelevance>& relevance, double min_share = 0.02);

}  // namespace mb
