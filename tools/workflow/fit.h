#pragma once
// The `fit` use case (`motionblocks fit`, Python `motionblocks.fit`): refit chosen parameters of a diagram against a
// measurement by Levenberg–Marquardt, in the diagram's experiment mode, with 95 % confidence intervals. The command
// line and the Python module only fill FitSettings, call FitToMeasurement and print or convert its FitOutcome.

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram_document.h"
#include "engine/experiment_mode.h"
#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/measurement.h"

namespace mb {

struct FitSettings {
  MeasurementSettings measurement;      ///< column map, position column, derivative cut-off (as compare)
  std::vector<std::string> parameters;  ///< "block.param" to refit; empty: the diagram's "free" list
};

struct FitOutcome {
  DiagramFit result;                ///< estimates, standard errors, RMSE before/after, the fitted diagram
  ExperimentMode mode = ExperimentMode::kSimulation;
  std::vector<std::string> parameters;  ///< the names asked for (FitSettings::parameters or the free list)
  std::string diagram;              ///< the diagram's source (DiagramDocument::source)
  std::string measurement;          ///< the log's name, as given
  std::size_t samples = 0;          ///< rows of the log
  /// fit.json: DiagramFit::ToJson with "diagram", "measurement", "mode" and "samples".
  nlohmann::json ToJson() const;
};

/// Refits `settings.parameters` (or the document's free list) of `document` against `log`, named `measurement_name`
/// in the outcome. In equation-error mode the measured outputs and the model's get the same zero-phase low-pass at
/// settings.measurement.derivative_cutoff_hz (ModelComparison::set_output_filter), as compare does. A result whose
/// parameters cannot be estimated is returned with result.fit.identifiable false (the caller decides: the command
/// line exits 3). @throws std::invalid_argument when there is nothing to fit (no names and no "free" list), and as
/// FitDiagram; NumericalError as FitDiagram.
FitOutcome FitToMeasurement(const DiagramDocument& document, const MeasurementLog& log,
                            const std::string& measurement_name, const FitSettings& settings);

}  // namespace mb
