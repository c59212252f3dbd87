#include "blocks/from_file.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "engine/file_access.h"
#include "models/diagnosis/measurement_log.h"

namespace mb {

FromFile::FromFile(const BlockConfig& config) : Block(config.name) {
  const auto& p = config.parameters;
  const std::string& interpolation = p.String("interpolation");
  if (interpolation != "linear" && interpolation != "zoh") {
    throw std::invalid_argument("interpolation must be \"linear\" or \"zoh\", got \"" + interpolation + "\"");
  }
  zoh_ = interpolation == "zoh";
  std::filesystem::path path;
  try {
    path = ResolveDiagramFile(p.String("file"), config.base_directory);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("parameter file ") + e.what());
  }
  MeasurementLogOptions options;
  options.min_rows = 1;
  options.max_gap_ratio = 0.0;  // a reference profile may be sampled unevenly
  options.required_columns = {p.String("column")};
  const MeasurementLog log = ReadMeasurementLog(path.string(), options);
  const std::string& time_column = p.String("time_column");
  if (!time_column.empty() && time_column != log.names().front()) {
    throw std::invalid_argument("time_column \"" + time_column + "\" is not the first column of " + path.string() +
                                " (which is \"" + log.names().front() +
                                "\"); the time must be the first column, or leave time_column empty");
  }
  const Eigen::VectorXd& t = log.time();
  const Eigen::VectorXd& v = log.column(p.String("column"));
  time_.assign(t.data(), t.data() + t.size());
  values_.assign(v.data(), v.data() + v.size());
  DeclareOutputPort("y");
  if (zoh_) {
    DeclareDiscreteState(1);  // the current segment i, as a double
    DeclareZeroCrossings(1);
  }
  SetSampleTime(SampleTime::Continuous());
}

std::size_t FromFile::Segment(double t) const noexcept {
  const auto it = std::upper_bound(time_.begin(), time_.end(), t);
  return it == time_.begin() ? 0 : static_cast<std::size_t>(it - time_.begin()) - 1;
}

void FromFile::Initialize(const BlockContext& c) const {
  if (zoh_) c.discrete_state()(0) = static_cast<double>(Segment(c.time()));
}

void FromFile::CalcOutput(const BlockContext& c) const {
  const double t = c.time();
  if (zoh_) {
    c.y(0) = values_[static_cast<std::size_t>(c.discrete_state()(0))];
    return;
  }
  if (t <= time_.front()) {
    c.y(0) = values_.front();
    return;
  }
  if (t >= time_.back()) {
    c.y(0) = values_.back();
    return;
  }
  const std::size_t i = Segment(t);
  const double w = (t - time_[i]) / (time_[i + 1] - time_[i]);
  c.y(0) = values_[i] + w * (values_[i + 1] - values_[i]);
}

void FromFile::CalcZeroCrossings(const BlockContext& c) const {
  const auto i = static_cast<std::size_t>(c.discrete_state()(0));
  // After the last sample there is nothing left to locate: a constant positive value.
  c.zero_crossings()(0) = i + 1 < time_.size() ? c.time() - time_[i + 1] : 1.0;
}

bool FromFile::UpdateModes(const BlockContext& c) const {
  const auto segment = static_cast<double>(Segment(c.time()));
  const bool changed = segment != c.discrete_state()(0);
  c.discrete_state()(0) = segment;
  return changed;
}

MB_REGISTER_BLOCK(FromFile, BlockType{
    "from_file",
    "y(t) = a column of a CSV measurement log (time first), interpolated linearly or held (zoh); held outside "
    "the data's range.",
    {FileName("file", "CSV file, relative to the diagram's folder"),
     Optional("time_column", "", "", "name of the time column [s] (must be the first column; \"\" = first)",
              ParamType::kString),
     Required("column", "", "name of the column to output", ParamType::kString),
     Choice("interpolation", "linear", "\"linear\" or \"zoh\"", {"linear", "zoh"})},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<FromFile>(c); }})

}  // namespace mb
