#include "tools/workflow/gpr_training.h"

#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "tools/workflow/loop_from_diagram.h"

namespace mb {

namespace {

// M_n, B_n given, or read from the DOB of the diagram.
SmoothedDisturbanceOptions SmoothedOptions(const SmoothedTargetSettings& s) {
  SmoothedDisturbanceOptions so;
  so.cutoff_hz = s.cutoff_hz;
  if (!s.diagram.empty()) {
    const PaperLoop loop = PaperLoopFromDiagram(LoadDiagram(s.diagram));
    if (!loop.has_dob) {
      throw std::invalid_argument(fmt::format("fit-gpr --diagram {}: the diagram has no dob block to read the nominal "
                                              "plant from: give --nominal-mass and --nominal-damping",
                                              s.diagram));
    }
    so.nominal_mass = loop.nominal_mass;
    so.nominal_damping = loop.nominal_damping;
  }
  if (s.nominal_mass > 0.0) so.nominal_mass = s.nominal_mass;
  if (s.nominal_damping >= 0.0) so.nominal_damping = s.nominal_damping;
  if (!(so.nominal_mass > 0.0) || s.force_column.empty()) {
    throw std::invalid_argument("fit-gpr --target smoothed: give --force-column COL (the force the plant received "
                                "[N]) and the nominal plant: --nominal-mass M_n [kg] and --nominal-damping B_n "
                                "[N*s/m], or --diagram LOOP.json (its dob block's)");
  }
  if (so.nominal_damping < 0.0) so.nominal_damping = 0.0;
  return so;
}

}  // namespace

Table ReadGprTrainingTable(const std::string& path, GprTrainingSelection* selection,
                           const std::optional<SmoothedTargetSettings>& smoothed) {
  if (smoothed && !selection->disturbance_column.empty()) {
    throw std::invalid_argument("fit-gpr: --target smoothed computes the disturbance from time, position and force: "
                                "drop --disturbance-column (or use --target dob)");
  }
  if (!smoothed && selection->disturbance_column.empty()) {
    throw std::invalid_argument("fit-gpr: name the disturbance column (the DOB estimate): --disturbance-column COL");
  }
  if (!smoothed) {
    return ReadGprTable(path, {selection->position_column, selection->velocity_column, selection->disturbance_column});
  }
  const SmoothedDisturbanceOptions so = SmoothedOptions(*smoothed);
  Table log = ReadGprTable(path, {smoothed->time_column, selection->position_column, selection->velocity_column,
                                  smoothed->force_column});
  AddSmoothedDisturbanceColumn(log, smoothed->time_column, selection->position_column, smoothed->force_column, so,
                               kSmoothedDisturbanceColumn);
  selection->disturbance_column = kSmoothedDisturbanceColumn;
  return log;
}

std::string DescribeGprFit(const GprModel& model) {
  const GprModelData& m = model.data();
  const GprHyperparameters& h = m.hyperparameters;
  return fmt::format(
      "fit {} ({} solver) to {} samples: {} features, log marginal likelihood {:.6g}, {:.2f} s\n"
      "  signal_variance_x {:.6g}, length_scale_x {:.6g}, signal_variance_xdot {:.6g}, "
      "length_scale_xdot {:.6g} m/s, noise_variance {:.6g}, period {:.6g} m, mean {:.6g}\n"
      "  trained ranges: x [{:.6g}, {:.6g}] m, xdot [{:.6g}, {:.6g}] m/s\n",
      GprKernelName(m.kernel), m.provenance.solver, m.provenance.sample_count, model.feature_count(),
      m.provenance.log_marginal_likelihood, m.provenance.fit_seconds, h.signal_variance_x, h.length_scale_x,
      h.signal_variance_xdot, h.length_scale_xdot, h.noise_variance, h.period, m.mean, m.x_range.min,
      m.x_range.max, m.xdot_range.min, m.xdot_range.max);
}

}  // namespace mb
