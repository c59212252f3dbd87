#pragma once
// Finding the paper's loop (models/stability/stability.h's PaperLoop) in a diagram by what its blocks are, not
// by what they are called: the plant, the disturbance observer, the PD, the GP path and the feedforward are found
// by block type, or — where a type does not say it (a PD built of gains and a velocity estimator, two plants) —
// by the diagram's optional "roles" map (role → element name, diagrams/schema.json):
//
//   role                  block type            read                                          if absent
//   plant                 linear_motor          mass + payload_mass, damping                  the one such element
//                         rigid_body            mass, damping                                 (required)
//   dob                   dob                   nominal_mass, nominal_damping, cutoff_hz,     no DOB (has_dob = false)
//                                               relative_degree, discretization; its Ts
//   pd                    pd_controller         kp, kd, derivative_filter T_f, method; Ts     the one such element, else
//   pd_proportional_gain  gain                  K_p = gain                                    the three roles (required
//   pd_derivative_gain    gain                  K_d = gain                                    when there is no
//   pd_derivative_filter  velocity_estimator    derivative cut-off; Ts                        pd_controller)
//   gp_filter             f_gp                  weight α, cutoff_hz, order                    the one such element, or none
//   gp_velocity_filter    velocity_estimator    F_ẋ cut-off                                   the one velocity_estimator
//                                                                                             the PD does not use, or 100 Hz
//   gp                    gpr                   confidence_weighting                          the one such element, or none
//   adaptive_feedforward  adaptive_mass_feedforward  min_mass, max_mass (the clamp of Δm̂)  the one such element, or none
//   feedforward           nominal_inverse       (present or not)                              has_feedforward = any
//                                                                                             nominal_inverse of form
//                                                                                             "derivatives"
//
// A discrete pd_controller's filtered derivative is exactly the velocity-estimator form K_d(1 − a)(1 − z⁻¹)/
// (Ts(1 − a z⁻¹)) with a = T_f/(T_f + Ts) (backward Euler) or (2T_f − Ts)/(2T_f + Ts) (Tustin)
// (blocks/pd_controller.h), so it enters PaperLoop as the cut-off −ln(a)/(2π Ts) that gives the same a.
// Ts is the DOB's sample period, else the PD's.

#include "engine/diagram.h"
#include "models/gpr/gpr_model.h"
#include "models/stability/stability.h"

namespace mb {

/// Reads the loop from a built diagram (subsystems expanded, overrides applied), as the table above says.
/// @throws std::invalid_argument naming what is missing, duplicated (with the "roles" entry that settles it), of
/// the wrong type for its role, or not representable (a continuous PD; a pd_controller whose derivative pole
/// a ≤ 0: T_f = 0, or T_f ≤ Ts/2 with Tustin).
PaperLoop PaperLoopFromDiagram(const Diagram& diagram);

/// PaperLoopFromDiagram + AnalyseStability (models/stability/stability.h).
StabilityReport AnalyseStability(const Diagram& diagram, const GprModel* gpr = nullptr,
                                 const StabilityOptions& options = {});

}  // namespace mb
