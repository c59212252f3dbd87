#pragma once
// Where a simulation's logged samples go when they are not (only) kept in memory: Simulator::StreamLogTo hands each
// sample to a LogSink as it is taken, so that a long run's log costs no memory (engine/output_file.h CsvLogFile
// writes it to disk).

#include <string>
#include <vector>

namespace mb {

class LogSink {
 public:
  virtual ~LogSink() = default;
  /// Before the first sample: the logged column names (SignalLog::names, without the time).
  virtual void Begin(const std::vector<std::string>& names) = 0;
  /// One logged sample: time `t` [s] and one value per name. May throw (a write error stops the run).
  virtual void Append(double t, const std::vector<double>& values) = 0;
};

}  // namespace mb
