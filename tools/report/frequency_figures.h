#pragma once
// The frequency view of compare's report (as MATLAB's `tfestimate` on the record and on the model's simulation, and a
// linearised model's `bode`): Welch's H1 estimate and its coherence (models/diagnosis/frequency_response.h) from the
// measured input to the measured output and to the output the model simulates on that input — the same estimator on
// both, so a hybrid or nonlinear model is compared as it runs —, and the fitted diagram linearised about the record's
// operating point (engine/linearization.h), gain and phase, with a sentence saying where measured and model part.
//
// Which response: in simulation mode, from the first input connector whose measurement column the log holds to the
// compared output; in equation-error mode (motion in, force out), from the measured position to the output — the
// linearised model's response then sums its position, velocity and acceleration inputs' responses, each times the
// response of that input's column to the position's as the log holds it (the derivation's low-pass included; the
// ideal (j2πf)^order for a column the log lacks). The operating point holds each input at its mean over the log, a velocity at its median speed (the
// stage sliding, where a Coulomb law has no slope). A linearisation that does not respond to the input (its paths run
// through discrete blocks, which linearisation holds) is left out, with a sentence saying so.

#include <filesystem>

#include <nlohmann/json.hpp>

#include "engine/experiment_mode.h"
#include "models/diagnosis/measurement_log.h"
#include "tools/report/report.h"
#include "tools/workflow/comparison.h"

namespace mb {

/// Coherence above which the measured response is trusted when it is compared with the model's (γ² ≥ 0.8: at most
/// 20 % of the output's power at that frequency is not linear in the input).
inline constexpr double kTrustedCoherence = 0.8;

/// Adds the frequency view to `report`: figures `frequency_response_gain.png`, `frequency_response_phase.png` and
/// `frequency_response_coherence.png` in `out`, and a paragraph. `diagram` (built against `base_directory`) is the
/// fitted model, `output` the compared output (measured and simulated series on the log's rows). What cannot be shown
/// (no input column, a diagram that cannot be built or linearised, a record shorter than 64 samples) becomes a
/// paragraph saying why. @throws std::runtime_error if a figure's CSV cannot be written.
void AddFrequencyResponseFigures(HtmlReport* report, const std::filesystem::path& out, ExperimentMode mode,
                                 const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                                 const MeasurementLog& log, const ComparedOutput& output);

}  // namespace mb
