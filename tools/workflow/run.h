#pragma once
// Run: one `motionblocks run` as a library call (DiagramRun). The diagram simulated from its experiment's start to its
// stop time, its input connectors fed from CSV logs, its log streamed to a sink as it is taken (memory stays bounded
// however long the run) while its envelope is kept for figures (each stretch's minimum and maximum: no peak lost), its
// metrics accumulated sample by sample.
// Nothing is written here but what the sink writes: tools/report/run_report.h writes summary.json and report.html.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "engine/diagram.h"
#include "engine/simulator.h"

namespace mb {

/// What `run` is asked for.
struct RunSettings {
  /// Input connectors fed from CSV logs: "connector=FILE[:COLUMN]" (FeedInputsFromFiles, measurement.h).
  std::vector<std::string> inputs;
  /// Rows per signal kept in memory for the figures (the streamed log's envelope, Simulator::StreamLogTo); 0: none.
  std::size_t samples_in_memory = 20000;
};

/// What one run gave.
struct RunOutcome {
  /// log: the envelope (at most samples_in_memory rows); metrics: the diagram's metrics over every sample [SI];
  /// solver statistics; wall time of the simulation [s] (not counting the reading of the diagram and inputs).
  SimulationResult result;
  long long samples = 0;  ///< samples streamed to the sink
};

/// One run of a diagram, in two phases so that a command touches no file before the run is known to be possible:
/// the constructor builds the simulator and reads the inputs (everything a bad diagram or input file is refused
/// for), Execute simulates.
class DiagramRun {
 public:
  /// `diagram` (loaded, --set applied) must outlive the run.
  /// @throws std::invalid_argument as FeedInputsFromFiles (a bad spec, file or column) and as Simulator's
  /// construction (an algebraic loop, an unknown signal).
  DiagramRun(const Diagram& diagram, const RunSettings& settings);

  /// Simulates over the experiment's [start, stop] time, streaming every logged sample to `sink`
  /// (Simulator::StreamLogTo; the caller commits a file sink). `progress` gets the share done, 0…1, as the run goes
  /// (may be empty). Call once. @throws as Simulator::Initialize and AdvanceTo (a run over its cost limits, a solver
  /// failure: NumericalError).
  RunOutcome Execute(LogSink* sink, const std::function<void(double)>& progress = {});

 private:
  const Diagram& diagram_;
  Simulator sim_;
  std::size_t samples_in_memory_;
};

}  // namespace mb
