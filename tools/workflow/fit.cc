#include "tools/workflow/fit.h"

#include <stdexcept>

#include <fmt/format.h>

namespace mb {

using nlohmann::json;

json FitOutcome::ToJson() const {
  json summary = result.ToJson();
  summary["diagram"] = diagram;
  summary["measurement"] = measurement;
  summary["mode"] = mode;
  summary["samples"] = samples;
  return summary;
}

FitOutcome FitToMeasurement(const DiagramDocument& document, const MeasurementLog& log,
                            const std::string& measurement_name, const FitSettings& settings) {
  FitOutcome outcome;
  outcome.parameters = settings.parameters.empty() ? document.FreeParameters() : settings.parameters;
  if (outcome.parameters.empty()) {
    throw std::invalid_argument(fmt::format(
        "nothing to fit: {} has no \"free\" list; name the parameters to refit (command line: --fit block.param,…; "
        "Python: fit=['block.param', …])",
        document.source()));
  }
  outcome.mode = document.Mode();
  outcome.diagram = document.source();
  outcome.measurement = measurement_name;
  outcome.samples = static_cast<std::size_t>(log.rows());
  const double output_filter_hz =
      outcome.mode == ExperimentMode::kEquationError ? settings.measurement.derivative_cutoff_hz : 0.0;
  outcome.result = FitDiagram(document.json(), document.base_directory(), document.source(), log,
                              settings.measurement.column_map, outcome.parameters, output_filter_hz);
  return outcome;
}

}  // namespace mb
