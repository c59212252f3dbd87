#pragma once
// What `motionblocks fit-gpr` fits the TISO-GPR to: a log's DOB-estimate column (the paper's target), or the smoothed
// inverse-model estimate M_n·ẍ + B_n·ẋ − u computed from its time, position and force (models/gpr/
// disturbance_target.h), with the nominal plant given or read from a loop diagram's dob block.

#include <optional>
#include <string>

#include "engine/table.h"
#include "models/gpr/disturbance_target.h"
#include "models/gpr/gpr_log.h"
#include "models/gpr/gpr_model.h"

namespace mb {

/// The smoothed target's inputs (fit-gpr --target smoothed).
struct SmoothedTargetSettings {
  std::string time_column = "time_s";
  std::string force_column;  ///< the force the plant received [N]; required
  /// A loop diagram whose dob block gives M_n and B_n; "" = none (then nominal_mass is required).
  std::string diagram;
  double nominal_mass = 0.0;      ///< M_n [kg]; > 0 overrides the diagram's
  double nominal_damping = -1.0;  ///< B_n [N·s/m]; >= 0 overrides the diagram's (else 0)
  double cutoff_hz = SmoothedDisturbanceOptions{}.cutoff_hz;  ///< the zero-phase low-pass [Hz]
};

/// The column the smoothed estimate is appended under.
inline constexpr const char* kSmoothedDisturbanceColumn = "smoothed_disturbance";

/// The training table of a fit: the log at `path` with the selection's columns; with `smoothed`, also its time and
/// force columns, the smoothed estimate appended as kSmoothedDisturbanceColumn and `selection` pointed at it.
/// @throws std::invalid_argument (fit-gpr's words) when the disturbance column is missing without `smoothed` or given
/// with it, when the smoothed target lacks its force column or nominal plant, or the diagram has no dob block; and
/// as ReadGprTable, LoadDiagram and AddSmoothedDisturbanceColumn.
Table ReadGprTrainingTable(const std::string& path, GprTrainingSelection* selection,
                           const std::optional<SmoothedTargetSettings>& smoothed);

/// What `motionblocks fit-gpr` says of a fitted model, three lines each ending in '\n': the kernel, solver, samples,
/// features, log marginal likelihood and fit time; the hyperparameters; the trained ranges of x and ẋ.
std::string DescribeGprFit(const GprModel& model);

}  // namespace mb
