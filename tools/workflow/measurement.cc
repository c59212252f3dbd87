#include "tools/workflow/measurement.h"
#include "tools/workflow/measurement_in_memory.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "engine/units.h"
#include "models/diagnosis/quantization_floor.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {

using nlohmann::json;

std::string PositionUnitToken(const std::string& position_column) {
  const std::string unit = ColumnUnit(position_column);
  if (QuantityOfUnit(unit) == MotionQuantity::kPosition) return unit;
  // A unit of no motion quantity standing for the position (x_V on an electronic oscillator) stays that unit; a
  // length in another unit (mm) is converted to metres (PositionToMetres), no suffix is read as metres.
  if (!unit.empty() && QuantityOfUnit(unit) == MotionQuantity::kOther && !UnitFactor(unit, "m")) return unit;
  return "m";
}

std::string DerivedVelocityColumn(const std::string& position_column) {
  return "velocity_" + PositionUnitToken(position_column) + "_s";
}

std::string DerivedAccelerationColumn(const std::string& position_column) {
  return "acceleration_" + PositionUnitToken(position_column) + "_s2";
}

MeasurementLog ReadMeasurementWithDerivatives(const std::string& path, const std::string& position_column,
                                              double derivative_cutoff_hz,
                                              const std::vector<std::string>& filter_columns,
                                              const std::vector<std::string>& held_columns) {
  return AddMeasurementDerivatives(IntakeMeasurementLog(path), position_column, derivative_cutoff_hz, filter_columns,
                                   held_columns);
}

double DerivativeCutoffHz(double cutoff_hz, double sample_period, const std::string& source) {
  if (!(sample_period > 0.0)) {
    throw std::invalid_argument(fmt::format("{}: the sample period {} s is not positive", source, sample_period));
  }
  const double rate = 1.0 / sample_period;
  if (cutoff_hz == kAutomaticCutoffHz) {
    const double share = kAutomaticCutoffShare * rate;  // exactly 100 Hz from 500 Hz up, whatever the rounding
    return share < kAutomaticCutoffHz * (1.0 - 1e-9) ? share : kAutomaticCutoffHz;
  }
  if (!(cutoff_hz > 0.0 && cutoff_hz < 0.5 * rate)) {
    throw std::invalid_argument(fmt::format(
        "{}: the derivative cut-off {:g} Hz must lie above 0 and below the Nyquist frequency {:.4g} Hz of this log "
        "(sampled at {:.4g} Hz); pass a cut-off below {:.4g} Hz, e.g. --derivative-cutoff-hz {:.3g} ({:g} × the sample "
        "rate), or leave it out: the default follows the sample rate",
        source, cutoff_hz, 0.5 * rate, rate, 0.5 * rate, kAutomaticCutoffShare * rate, kAutomaticCutoffShare));
  }
  return cutoff_hz;
}

double DerivativeCutoffHz(double cutoff_hz, const Eigen::VectorXd& time, const Eigen::VectorXd* position,
                          const std::string& source, double* quantization_share) {
  const double rate_limited = DerivativeCutoffHz(cutoff_hz, MedianTimeStep(time), source);
  if (cutoff_hz != kAutomaticCutoffHz || position == nullptr) return rate_limited;
  return QuantizationLimitedCutoff(time, *position, rate_limited, quantization_share);
}

double DerivativeCutoffHz(const MeasurementSettings& settings, const MeasurementLog& log) {
  const bool has_position = log.has_column(settings.position_column);
  return DerivativeCutoffHz(settings.derivative_cutoff_hz, log.time(),
                            has_position ? &log.column(settings.position_column) : nullptr, log.source());
}

double PositionToMetres(const std::string& position_column) {
  const std::string unit = ColumnUnit(position_column);
  const std::optional<double> factor = unit.empty() ? std::nullopt : UnitFactor(unit, "m");
  return factor.value_or(1.0);
}

MeasurementLog AddMeasurementDerivatives(const MeasurementLog& raw, const std::string& position_column,
                                         double derivative_cutoff_hz, const std::vector<std::string>& filter_columns,
                                         const std::vector<std::string>& held_columns) {
  const double dt = MedianTimeStep(raw.time());
  const double to_metres = PositionToMetres(position_column);
  // Resolved when first needed: a log that is neither filtered nor differentiated needs no cut-off. The automatic one
  // comes down for a coarse encoder (QuantizationLimitedCutoff), on the position as the log will hold it.
  std::optional<double> cutoff_hz;
  double quantization_share = 0.0;
  const auto cutoff = [&] {
    if (!cutoff_hz) {
      std::optional<Eigen::VectorXd> position;
      if (raw.has_column(position_column)) position = raw.column(position_column) * to_metres;
      cutoff_hz = DerivativeCutoffHz(derivative_cutoff_hz, raw.time(), position ? &*position : nullptr, raw.source(),
                                     &quantization_share);
    }
    return *cutoff_hz;
  };
  const auto& segments = raw.segment_starts();
  std::vector<std::string> names = raw.names();
  std::vector<Eigen::VectorXd> columns;
  std::vector<std::string> held;
  const auto listed = [](const std::vector<std::string>& list, const std::string& name) {
    return std::find(list.begin(), list.end(), name) != list.end();
  };
  for (const auto& name : names) {
    Eigen::VectorXd column = raw.column(name);
    if (name == position_column) column *= to_metres;
    if (listed(held_columns, name)) {
      column = HeldSignalAtSampleInstants(column, segments);
      held.push_back(name);
    }
    if (listed(filter_columns, name)) column = ZeroPhaseLowPassBySegment(column, dt, cutoff(), segments);
    columns.push_back(std::move(column));
  }
  MeasurementLog log(names, columns, raw.source());
  log.SetSegmentStarts(segments);
  for (const auto& note : raw.notes()) log.AddNote(note);
  const std::string velocity = DerivedVelocityColumn(position_column);
  const std::string acceleration = DerivedAccelerationColumn(position_column);
  if (to_metres != 1.0 && log.has_column(position_column)) {
    // One flag does it (issue 40, item 8): a diagram whose position connector reads metres finds them without --map.
    const bool alias = !log.has_column(kMetresPositionColumn);
    if (alias) log.AddColumn(kMetresPositionColumn, log.column(position_column));
    log.AddNote(fmt::format("{}: the position column '{}' is in {} (its name's suffix): converted to metres (× {:g}) "
                            "and keeps its name{}; the derived {} and {} are in m/s and m/s²",
                            raw.source(), position_column, ColumnUnit(position_column), to_metres,
                            alias ? fmt::format(", also as '{}' for a diagram that reads metres", kMetresPositionColumn)
                                  : std::string(),
                            velocity, acceleration));
  }
  for (const auto& name : held) {
    log.AddNote(fmt::format("{} is a held command (intersample zoh): compared at the mean of each pair of samples, the "
                            "held value over the sample period centred on each instant, where the motion's central "
                            "differences see it (half a sample, {:.3g} ms, later than logged)",
                            name, 500.0 * dt));
  }
  if (log.has_column(position_column) && (!log.has_column(velocity) || !log.has_column(acceleration))) {
    const MotionDerivatives m = DeriveMotionBySegment(log.time(), log.column(position_column), cutoff(), segments);
    if (!log.has_column(velocity)) log.AddColumn(velocity, m.velocity);
    if (!log.has_column(acceleration)) log.AddColumn(acceleration, m.acceleration);
  }
  const double rate_limited = DerivativeCutoffHz(derivative_cutoff_hz, dt, raw.source());
  if (cutoff_hz && *cutoff_hz < rate_limited) {
    log.AddNote(fmt::format("{}: the position '{}' is logged in steps of {:.4g} (an encoder's count): differentiated "
                            "with the low-pass at {:.4g} Hz its quantization would be more than {:g} % of the derived "
                            "acceleration; the automatic cut-off came down to {:.4g} Hz, where it is {:.1f} % (choose "
                            "another with --derivative-cutoff-hz)",
                            raw.source(), position_column, QuantizationStep(log.column(position_column)), rate_limited,
                            100.0 * kMaxQuantizationShare, *cutoff_hz, 100.0 * quantization_share));
  }
  if (cutoff_hz && rate_limited != derivative_cutoff_hz) {
    log.AddNote(fmt::format("{}: sampled at {:.4g} Hz (Nyquist {:.4g} Hz): the default derivative cut-off {:g} Hz "
                            "became {:g} × the sample rate, {:.4g} Hz, for the zero-phase low-pass before "
                            "differentiating and for the filtered columns (choose another with "
                            "--derivative-cutoff-hz)",
                            raw.source(), 1.0 / dt, 0.5 / dt, kAutomaticCutoffHz, kAutomaticCutoffShare, rate_limited));
  }
  return log;
}

std::vector<std::string> OutputColumns(const json& diagram, const std::map<std::string, std::string>& column_map) {
  std::vector<std::string> out;
  for (const auto& c : DiagramDocument(diagram).Connectors("output")) {
    auto it = column_map.find(c.name);
    out.push_back(it != column_map.end() ? it->second : c.measurement);
  }
  return out;
}

InputSeries SeriesOf(const MeasurementLog& log, const std::string& column) {
  const auto& t = log.time();
  const auto& v = log.column(column);
  return InputSeries{std::vector<double>(t.data(), t.data() + t.size()), std::vector<double>(v.data(), v.data() + v.size())};
}

void FeedInputsFromFiles(const Diagram& diagram, const std::vector<std::string>& specs, Simulator* sim) {
  for (const auto& spec : specs) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos) {
      throw std::invalid_argument(fmt::format("--input '{}': write connector=FILE or connector=FILE:COLUMN", spec));
    }
    const std::string connector = spec.substr(0, eq);
    std::string file = spec.substr(eq + 1);
    std::string column;
    if (const auto colon = file.rfind(':'); colon != std::string::npos) {
      column = file.substr(colon + 1);
      file = file.substr(0, colon);
    }
    if (column.empty()) {
      for (const auto& in : diagram.inputs()) {
        if (in.name == connector) column = in.measurement;
      }
    }
    const MeasurementLog log = ReadMeasurementLog(file, MeasurementLogOptions{{column}});
    sim->SetInput(connector, SeriesOf(log, column));
  }
}

ExperimentMode ModeOf(const json& diagram) { return DiagramDocument(diagram).Mode(); }

namespace {

// The measured outputs an equation-error diagram filters like the motion (IDIM-LS's parallel filtering).
std::vector<std::string> FilteredColumns(const json& diagram, const MeasurementSettings& settings) {
  return ModeOf(diagram) == ExperimentMode::kEquationError ? OutputColumns(diagram, settings.column_map)
                                                            : std::vector<std::string>{};
}

// Those of them that are held commands (settings.intersample zoh).
std::vector<std::string> HeldColumns(const json& diagram, const MeasurementSettings& settings) {
  return settings.intersample == Intersample::kZeroOrderHold ? FilteredColumns(diagram, settings)
                                                             : std::vector<std::string>{};
}

}  // namespace

Intersample ParseIntersample(const std::string& text) {
  if (text == "foh") return Intersample::kFirstOrderHold;
  if (text == "zoh") return Intersample::kZeroOrderHold;
  throw std::invalid_argument(fmt::format("intersample '{}': write foh (a sample is the value at its instant: a "
                                          "sensor) or zoh (a sample is held until the next: a logged command)",
                                          text.substr(0, 40)));
}

const char* IntersampleName(Intersample intersample) {
  return intersample == Intersample::kZeroOrderHold ? "zoh" : "foh";
}

MeasurementLog ReadMeasurementFor(const json& diagram, const std::string& path, const MeasurementSettings& settings) {
  return ReadMeasurementWithDerivatives(path, settings.position_column, settings.derivative_cutoff_hz,
                                        FilteredColumns(diagram, settings), HeldColumns(diagram, settings));
}

namespace {

// What a log file's reader refuses (engine/table.h), for columns in memory: a value that is not finite, a time that
// decreases. Rows are counted from 0, as NumPy indexes them.
void CheckColumns(const std::vector<std::string>& names, const std::vector<Eigen::VectorXd>& columns) {
  for (std::size_t c = 0; c < columns.size(); ++c) {
    for (Eigen::Index i = 0; i < columns[c].size(); ++i) {
      if (!std::isfinite(columns[c](i))) {
        throw std::invalid_argument(fmt::format("measurement: column '{}' row {} is {}: give finite values (drop or "
                                                "interpolate that sample)",
                                                names[c], i, columns[c](i)));
      }
    }
  }
  const Eigen::VectorXd& t = columns.front();
  for (Eigen::Index i = 1; i < t.size(); ++i) {
    if (t(i) < t(i - 1)) {
      throw std::invalid_argument(fmt::format("measurement: time '{}' decreases at row {} ({} s after {} s): sort the "
                                              "samples by time",
                                              names.front(), i, t(i), t(i - 1)));
    }
  }
}

}  // namespace

MeasurementLog MeasurementOfColumns(const std::vector<std::pair<std::string, Eigen::VectorXd>>& given,
                                    const std::string& source) {
  if (given.empty()) throw std::invalid_argument("measurement: no columns given; give time_s and the measured columns");
  std::vector<std::string> names;
  std::vector<Eigen::VectorXd> columns;
  for (const auto& [name, column] : given) {
    if (!columns.empty() && column.size() != columns.front().size()) {
      throw std::invalid_argument(fmt::format("measurement: column '{}' has {} values, '{}' has {}: give every column "
                                              "one value per sample",
                                              name, column.size(), names.front(), columns.front().size()));
    }
    const bool time = name == "time_s";
    names.insert(time ? names.begin() : names.end(), name);
    columns.insert(time ? columns.begin() : columns.end(), column);
  }
  CheckColumns(names, columns);
  return MeasurementLog(names, columns, source);
}

MeasurementLog TakeMeasurementFor(const json& diagram, const MeasurementLog& raw, const MeasurementSettings& settings) {
  return AddMeasurementDerivatives(IntakeMeasurementLog(raw), settings.position_column, settings.derivative_cutoff_hz,
                                   FilteredColumns(diagram, settings), HeldColumns(diagram, settings));
}

}  // namespace mb
