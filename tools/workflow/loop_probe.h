#pragma once
// Simulation mode's closed loop, measured on the diagram itself (issue 46, item 1): the response of the compared output
// to a small force added at the plant's force input — the loop linearised along the record — from which the
// diagnosis passes every candidate force through the loop (models/diagnosis/loop_response.h). The diagram is probed as
// Simulink's `linmod` probes a model, by perturbation, but along the record's own trajectory and through its discrete
// controller (which `linmod` would hold open): a step of δ into the plant's input while the axis moves, simulated, minus
// the same simulation without it, over δ.

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "engine/diagram_document.h"
#include "models/diagnosis/effect_catalogue.h"
#include "models/diagnosis/loop_response.h"
#include "tools/workflow/comparison.h"

namespace mb {

/// The diagram's one plant: the element of a type with the loop role "plant" (engine/block_roles.h); none, with the
/// reason in `why`, when there is none or more than one.
std::optional<std::string> PlantElement(const DiagramDocument& d, std::string* why);
/// Where a force acts on the plant (PlantElement): its only driven input, else its port "f" or "u"; none, with the
/// reason in `why`.
std::optional<Endpoint> PlantForcePort(const DiagramDocument& d, std::string* why);

/// The probe's result: the loop (null when the diagram cannot be probed) and a sentence for the notes.
struct LoopProbe {
  std::shared_ptr<const LoopResponse> loop;
  /// The drive force's response to the same load (the controller's reaction; null without a drive force or response).
  std::shared_ptr<const LoopResponse> drive_force;
  std::string note;  ///< how it was measured (the plant's port, δ, the static gain, how long the response lasts), or why not
};

/// Probes `comparison`'s diagram (simulation mode; its parameters as they are now), whose primary output `nominal`
/// was just simulated. The plant is the one element of a type with the loop role "plant" (engine/block_roles.h); the
/// force enters at its only driven input (else its port "f" or "u"). δ = 1e-4 × the RMS of the signal driving that
/// port (`own`: ModelComparison::SimulateBlockOutputs), the step at the start of the longest stretch where |velocity|
/// (N, measured) exceeds a tenth of its maximum; h[k] = s[k] − s[k − 1] of the response s to a load step (−1 × the
/// response to the pushing δ, per unit: LoopResponse's sign) over that stretch (where
/// the axis sticks again a force no longer moves it), kept up to where it holds all but 1e-6 of its energy. Returns a null loop with the reason when there is no single plant, no force port,
/// no motion or no response. With `drive_force` (ModelDriveForce's source, one of `own`'s signals), the same probe
/// also gives that signal's response to the load (LoopProbe::drive_force). @throws what ModelComparison throws (the
/// diagram fails to simulate).
LoopProbe ProbeLoop(const ModelComparison& comparison, const ComparedOutput& nominal,
                    const std::vector<std::pair<std::string, Eigen::VectorXd>>& own, const Eigen::VectorXd& velocity,
                    const std::optional<Endpoint>& drive_force = std::nullopt);

/// The compared output's change when an effect's block goes into `comparison`'s diagram (simulation mode; its
/// parameters as they are now) as `improve` adds it — SuggestAmendedDiagram after the drive force `drive_force`, with
/// the effect's parameters and no coefficients (its physical one) — simulated along the record, minus `nominal`: N
/// samples [the output's unit] (DiagnosisSignals::simulate_effect). Each call builds and simulates its own copy of the
/// diagram (callable from several threads at once). The callable throws what SuggestAmendedDiagram and the simulation
/// throw (std::invalid_argument, std::runtime_error).
std::function<Eigen::VectorXd(const EffectInstance&)> EffectSimulator(const ModelComparison& comparison,
                                                                      const ComparedOutput& nominal,
                                                                      const std::optional<Endpoint>& drive_force);

/// The model's drive force in simulation mode — what a force constant multiplies (DiagnosisSignals::drive_force) —
/// and a sentence for the notes saying where it was read; an empty force, with the reason, when the diagram shows none.
struct DriveForce {
  Eigen::VectorXd force;  ///< N samples, in the unit of the signal it was read from (N, N·m or A)
  std::optional<Endpoint> source;  ///< the diagram's signal it is (an element's output), for the blocks improve adds
  std::string note;
};

/// Reads the drive force from the simulated diagram, the first of:
///  1. a compared output after the primary whose unit is a force (N, N·m, or A for a drive's current): the force the
///     user compares is the drive's (EMPS: `force` ← gtau.y);
///  2. the diagram's own signal (`own`, ModelComparison::SimulateBlockOutputs) that a logged column in a force unit is
///     (`reactions`: log column → the own signal it matched): the drive's command the log holds, under its name in
///     the diagram;
/// else none, with a note saying what to add (the net force into the plant is not taken: for a rigid body it is M·a,
/// and the force constant's products of it would be the inertia's).
DriveForce ModelDriveForce(const DiagramDocument& d, const std::vector<ComparedOutput>& outputs,
                           const std::vector<std::pair<std::string, Eigen::VectorXd>>& own,
                           const std::vector<std::pair<std::string, std::string>>& reactions);

}  // namespace mb
