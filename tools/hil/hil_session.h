#pragma once
// A hardware-in-the-loop session as a library call (`motionblocks hil`, docs/hil.md): the diagram prepared (its plant
// subsystem swapped for the I/O subsystem of HIL blocks, --set overrides applied, the duration set), the board opened
// (a Quanser board, or the UDP virtual board talking to `motionblocks virtual-stage`), the rest of the diagram run at
// its sample time in real time (hw/hil_runner.h RunHilLoop), and OUT/signals.csv (as `run` writes it, so `compare`
// reads it), OUT/timing.csv (per tick) and OUT/summary.json (HilSessionResult::ToJson) written. The files an earlier
// run left in the output folder are removed before the loop starts, so a run killed in the loop leaves none of them.
// A safe stop is no exception: the result says `completed` false and why (the command line then exits 1).
//
// One call: RunHilSession(settings, stop). Its phases, for a caller with its own board: PrepareHilDiagram,
// OpenHilBoard, RunHilSessionOnBoard.

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hw/board.h"
#include "hw/hil_runner.h"
#include "hw/quanser_board.h"
#include "hw/udp_board.h"

namespace mb {

/// The I/O board a session runs against.
enum class HilBoardKind {
  kUdp,      ///< the UDP virtual board: `motionblocks virtual-stage` on 127.0.0.1 (no hardware)
  kQuanser,  ///< a Quanser board through the HIL SDK (a build with -DWITH_QUANSER=ON)
};

/// "udp" → kUdp, "quanser" → kQuanser (the `hil --board` values). @throws std::invalid_argument for another name.
HilBoardKind ParseHilBoardKind(const std::string& name);
/// The name ParseHilBoardKind reads: "udp" or "quanser".
std::string HilBoardName(HilBoardKind kind);

/// What a HIL session is asked for; every default of `motionblocks hil` is here (the board's and the loop's in
/// their own option structs, hw/).
struct HilSessionSettings {
  std::string diagram;                    ///< the diagram file (its plant is a subsystem element), as given
  std::vector<std::string> replacements;  ///< "ELEMENT=FILE" (SubsystemReplacement); at least one is required
  std::vector<std::string> overrides;     ///< "block.param=value" (ParameterOverride)
  double duration = 0.0;                  ///< run this long [s], in (0, kHilMaxDuration]; 0: the diagram's stop time
  std::filesystem::path out = "out/hil";  ///< output folder (created when the files are written)
  HilBoardKind board = HilBoardKind::kUdp;
  /// kUdp: the stage's port (stage_port; 0 is no port: Start fails naming it), reply_timeout [s], connect_timeout [s].
  UdpBoardOptions udp;
  /// kQuanser: board type and identifier, channels read and written, the hardware watchdog's timeout [s].
  QuanserBoardOptions quanser;
  /// The safe-stop streaks (max_missed_streak, max_overrun_streak) and the real-time options (SCHED_FIFO priority,
  /// lock memory). Its stop_request is not read: the session's own `stop` argument takes its place.
  HilOptions loop;
};

/// The names of the files a session writes into its output folder (signals.csv, timing.csv, summary.json), for
/// RefuseOutputsOverInputs (tools/report/output_files.h).
const std::vector<std::string>& HilSessionOutputNames();

/// The diagram ready for the board: what PrepareHilDiagram made.
struct PreparedHilDiagram {
  nlohmann::json json;                ///< the diagram JSON: replacements, overrides and duration applied
  std::vector<std::string> dropped;   ///< what the replacements dropped ("logged signal plant/x", …), in order
};

/// Prepares settings.diagram: refuses an output folder holding an input under a name the session writes (before any
/// board is opened), reads the diagram, swaps each replaced subsystem (allowing the diagram to read files in the
/// replacement's folder, process-wide: engine/file_access.h AllowDiagramFilesUnder), applies the overrides and sets
/// the experiment's duration when settings.duration > 0.
/// @throws std::invalid_argument without a replacement ("hil: give --replace plant=HIL_IO.json: …") or for a
/// malformed one or override; OutputReplacesInputError (tools/report/output_files.h); as ReadDiagramJson,
/// ReplaceSubsystem and ApplyOverrides (DiagramError).
PreparedHilDiagram PrepareHilDiagram(const HilSessionSettings& settings);

/// Opens the board settings.board names with its options. @throws std::runtime_error (a socket that cannot be
/// opened; the Quanser SDK's message, or how to build with it).
std::unique_ptr<IoBoard> OpenHilBoard(const HilSessionSettings& settings);

/// What the session is about to run, told just before its loop starts.
struct HilSessionStart {
  std::string name;      ///< the diagram's name
  std::string board;     ///< the board's description (IoBoard::description)
  double duration = 0.0; ///< stop − start time of the experiment [s]
  double period = 0.0;   ///< the loop's sample period [s] (HilLoopPeriod)
};

/// What `motionblocks hil` says as the loop starts: "hil NAME on BOARD: DURATION s at RATE Hz".
std::string DescribeHilSessionStart(const HilSessionStart& start);

/// What `motionblocks hil` says (on stderr) of an item a replacement dropped (PreparedHilDiagram::dropped): "hil:
/// dropped logged signal plant/x (it names the replaced plant)".
std::string DescribeHilDroppedItem(const std::string& dropped);

/// What one session gave: the content of summary.json, and the loop's log and timing records.
struct HilSessionResult {
  std::string diagram;                              ///< the diagram file, absolute
  std::string name;                                 ///< the diagram's name
  std::vector<std::string> overrides;               ///< as in the settings
  std::vector<std::string> replacements;            ///< as in the settings
  std::map<std::string, std::string> metric_units;  ///< metric → its unit
  std::string board;                                ///< the board's description
  /// The loop's result: the logged signals, metrics [SI] (or metrics_error), loop statistics [s], per-tick timing,
  /// completed / stop_reason / stop_time [s], the real-time notes.
  HilResult run;

  /// summary.json: diagram, name, overrides, replacements, metrics, metric_units, samples (logged samples per
  /// signal), metrics_error (when the metrics are missing), and hil: board, completed, stop_reason, stop_time_s,
  /// realtime (notes), loop (ticks, period_s, latency_s {mean, p50, p99, p99.9, max}, period_jitter_s {rms, max_abs},
  /// compute_s {mean, p99, max}, overruns, max_overrun_streak, missed_samples, max_missed_streak; times in s).
  nlohmann::json ToJson() const;
};

/// Runs the prepared diagram against `board` (opened, not started): builds it with the board attached
/// (hw/board_registry.h), tells `on_start` (may be empty) what it will run, removes the files an earlier session
/// left in settings.out (HilSessionOutputNames and killed writers' "<name>.tmp<pid>", never an input), runs the loop
/// (RunHilLoop: the board is started there and always safe-stopped) and writes signals.csv, timing.csv and
/// summary.json into settings.out. `stop` (may be null) is polled once per tick: true requests a safe stop (set it
/// from a signal handler). A safe stop returns a result with run.completed false; the files are written.
/// @throws as BuildDiagram (DiagramError: e.g. no HIL blocks for this board); std::invalid_argument from
/// HilLoopPeriod (continuous states, a period not a multiple of the fastest); std::runtime_error for an earlier
/// file that cannot be removed, from Board::Start (e.g. no virtual stage answers) or for a file that cannot be
/// written; an exception of a block in the loop, after the safe stop. A throw before the loop ended writes no file.
HilSessionResult RunHilSessionOnBoard(const HilSessionSettings& settings, const nlohmann::json& prepared_diagram,
                                      IoBoard& board, const std::atomic<bool>* stop,
                                      const std::function<void(const HilSessionStart&)>& on_start = {});

/// The whole session: PrepareHilDiagram, `on_dropped` (may be empty) for each dropped item, OpenHilBoard,
/// RunHilSessionOnBoard. @throws as those.
HilSessionResult RunHilSession(const HilSessionSettings& settings, const std::atomic<bool>* stop,
                               const std::function<void(const std::string&)>& on_dropped = {},
                               const std::function<void(const HilSessionStart&)>& on_start = {});

/// What `motionblocks hil` prints once the session's files are written into `out`: the real-time notes, the loop's
/// statistics (ticks, rate, latency, period jitter, compute time [µs], overruns, missed samples), the metrics and the
/// files written.
void PrintHilSessionSummary(const HilSessionResult& result, const std::string& out, std::ostream& os);

}  // namespace mb
