#pragma once
// from_file: a signal read from a CSV measurement log, interpolated in time (Simulink's From File /
// From Spreadsheet). The file format is models/diagnosis/measurement_log.h's: a header row with the column
// names, then one row of numbers per sample, the time column first and strictly increasing.

#include <vector>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y(t) = column value at t. Port: out "y". Parameters:
///  - file: the CSV path, relative to the diagram's folder (BlockConfig::base_directory); it must lie in that
///    folder or one allowed with --allow-path and be a regular file (engine/file_access.h);
///  - time_column: the time column's name [s] ("" = the first column; if given it must be the first column,
///    as the measurement-log format requires);
///  - column: the column to output;
///  - interpolation: "linear" (default) or "zoh" (hold the latest sample: y = v_i for t_i ≤ t < t_{i+1}).
/// Outside the data's time range the first/last value is held. "linear" is continuous in t and evaluated from t
/// directly. With "zoh" the segment i is a mode in the discrete state, frozen between events (y = v_i), and a
/// zero crossing g = t − t_{i+1} makes the solver stop at every sample time, where the output jumps (the same
/// event handling and engine caveat as the step block, blocks/step.h).
/// The file is read once, in the constructor. @throws std::invalid_argument / std::runtime_error (from
/// ReadMeasurementLog) naming the file, line and column for an unreadable file, a missing column, non-numeric
/// cells or a time that does not increase; std::invalid_argument for an unknown interpolation or a wrong
/// time_column.
class FromFile final : public Block {
 public:
  explicit FromFile(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcZeroCrossings(const BlockContext& context) const override;
  bool UpdateModes(const BlockContext& context) const override;

  /// The samples read (time [s] and values), for inspection.
  const std::vector<double>& time() const { return time_; }
  const std::vector<double>& values() const { return values_; }

 private:
  /// Index i of the last sample with t_i ≤ t (0 before the first sample).
  std::size_t Segment(double t) const noexcept;

  std::vector<double> time_;
  std::vector<double> values_;
  bool zoh_ = false;
};

}  // namespace mb
