#pragma once
// A measurement log given in memory rather than as a file (the Python module's arrays and dicts of columns): the same
// intake and derived motion as ReadMeasurementFor (tools/workflow/measurement.h). Implemented in measurement.cc.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/measurement.h"

namespace mb {

/// A raw measurement log from named columns in memory, the one named time_s first (else the first given), named
/// `source` in messages. @throws std::invalid_argument naming the column and the row (counted from 0, as NumPy
/// indexes) for what a log file's reader refuses: no columns, columns of different lengths, a value that is not
/// finite, a time that decreases.
MeasurementLog MeasurementOfColumns(const std::vector<std::pair<std::string, Eigen::VectorXd>>& columns,
                                    const std::string& source);

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
