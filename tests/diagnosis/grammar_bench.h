#pragma once
// The grammar-draw benchmark (issue 45, item 6; tests/diagnosis/grammar_draws.h): each draw's training and validation
// records are written as CSV, read back as `compare` reads them, compared and diagnosed with the user's diagram
// (diagrams/emps/rigid_body.json on a linear draw, diagrams/rotary/rigid_arm.json on a rotary one;
// CompareAndDiagnose), then improved (ImproveModel with the validation record) — the path of independent_bench.h.
//
// The judging:
//  - named right: the first effect outside the friction-law replacements (EffectTraits::friction_law_replacement) has
//    the draw's multiplier and modulator (EffectType::multiplier, ::modulator; FactorsOf), or, for a draw that is no
//    product (hysteresis: GrammarDraw::effect), is that effect;
//  - parameter right: named right, and its key shape parameter within the draw's tolerance (GrammarDraw::key_*; a
//    window's off time too); a column modulator's column is the draw's active one (DiagnosedEffect::log_column);
//  - floor reached: improve's held-out RMSE within [0.7, 1.3] × the draw's floor: the base truth's force on the
//    effect-free twin of the validation record, evaluated on the motion as compare derives it and low-passed as compare
//    filters, against the twin's logged force as read;
//  - a noise-only draw is clean when nothing outside the friction-law replacements is named with a share
//    (DiagnosedEffect::score) of 0.02 or more (its friction law is tanh-regularised: a regularised Coulomb law is the
//    base's law corrected, not an effect).

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tests/diagnosis/grammar_draws.h"

namespace mb::grammar {

/// The multiplier and modulator ids of a registered effect ("", "" for an effect that is not a product: time_delay,
/// resonance, drive_saturation, the friction-law replacements, …). Reads EffectType::multiplier and ::modulator.
std::pair<std::string, std::string> FactorsOf(const std::string& effect);

struct DrawResult {
  GrammarDraw draw;
  std::vector<std::string> details;  ///< each named effect with its score and parameters, then compare's notes
  std::string named_first;           ///< the first effect outside the friction-law replacements ("" = none)
  double named_score = 0.0;          ///< its share
  std::string named_pair;            ///< its multiplier×modulator, its name when not a product, "nothing"
  double parameter = 0.0;            ///< its key parameter (NaN when not named or absent)
  double second_parameter = 0.0;     ///< its second shape parameter where the draw has one (a window's off time), or NaN
  std::string log_column;            ///< its column (DiagnosedEffect::log_column)
  /// The third factor it carries (models/diagnosis/amplitude_factor.h): "time", its column's name, or "" for none.
  std::string third_found;
  double third_slope = 0.0;          ///< its amplitude's relative change per unit of its source (amplitude_slope)
  /// The drawn third factor is part of the force law named: a multiplier × 1 whose amplitude follows time or a column
  /// is that multiplier × time_ramp or × the column (grammar_bench.cc, LawOf), named either way.
  bool third_in_law = false;
  bool named_right = false, parameter_right = false, floor_reached = false;
  /// Named right with a change time as its key parameter (a step's, a window's on time): whether the interval the
  /// diagnosis gives for it (DiagnosedEffect::time_intervals) holds the drawn time, and its width as a share of the
  /// record.
  bool interval_judged = false, interval_holds = false;
  double interval_width = 0.0;
  /// Not named right, but the drawn pair is one the diagnosis said this record cannot tell from the one it named
  /// (DiagnosedEffect::alike): an honest "one of these two", counted apart.
  bool alike_right = false;
  bool clean = false;                ///< noise-only: nothing named with a share ≥ 0.02 outside the law replacements
  bool improve_run = false;
  /// The draw's own floor (improve runs only): improve run on the draw simulated without the effect, its held-out RMSE
  /// on that twin's validation record.
  double noise_floor = 0.0;
  double heldout_before = 0.0, heldout_after = 0.0;
  double compare_seconds = 0.0, improve_seconds = 0.0;
};

/// Runs one draw in `directory` (its logs written there); `run_improve` false: compare only.
DrawResult RunDraw(const GrammarDraw& draw, const std::filesystem::path& directory, bool run_improve);

/// The report (Markdown): pass rates, by multiplier and by modulator, the confusion table (rows: the drawn pair;
/// what was named first, with counts), the noise-only result and the times.
/// `title`: the report's heading.
std::string FormatReport(const std::vector<DrawResult>& draws, const std::vector<DrawResult>& noise_only,
                         const std::string& title = "Grammar draws");

/// The full confusion matrix as CSV (rows: drawn pairs; columns: what was named first; counts).
std::string ConfusionCsv(const std::vector<DrawResult>& draws);

/// One line per draw as CSV (seed, pair, named, parameter found and truth, verdicts, times).
std::string ResultsCsv(const std::vector<DrawResult>& draws);

}  // namespace mb::grammar
