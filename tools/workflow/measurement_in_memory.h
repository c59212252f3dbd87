#pragma once
// A measurement log given in memory rather than as a file (the Python module's arrays and dicts of columns): the same
// intake and derived motion as ReadMeasurementFor (tools/workflow/measurement.h). Implemented in measurement.cc.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/measurement.h"

namespace mb {

/// ReadMeasurementWithDerivatives on a log taken in already (IntakeMeasurementLog): its segments are kept.
MeasurementLog AddMeasurementDerivatives(const MeasurementLog& raw, const std::string& position_column,
                                         double derivative_cutoff_hz,
                                         const std::vector<std::string>& filter_columns = {},
                                         const std::vector<std::string>& held_columns = {});

/// ReadMeasurementFor on a log in memory (column 0 the time [s], not decreasing, every value finite):
/// IntakeMeasurementLog, then as ReadMeasurementFor. @throws as IntakeMeasurementLog.
MeasurementLog TakeMeasurementFor(const nlohmann::json& diagram, const MeasurementLog& raw,
                                  const MeasurementSettings& settings);

}  // namespace mb
