// motionblocks.run_hil_session: the `hil` command's library call (tools/hil/hil_session.h RunHilSession) — the
// diagram's plant subsystem swapped for the I/O subsystem and run in real time against the UDP virtual stage
// (`motionblocks virtual-stage`) or a Quanser board, signals.csv, timing.csv and summary.json written to `out`.
// Every default is HilSessionSettings'. Returns a HilSessionResult whose to_dict() is summary.json.

#include <signal.h>

#include <atomic>
#include <cstdint>

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "tools/hil/hil_session.h"

namespace mb::python {

namespace {

std::atomic<bool> g_stop_session{false};

extern "C" void StopSession(int) { g_stop_session.store(true); }

// While it lives, Ctrl-C (SIGINT) requests the session's safe stop, as in `motionblocks hil`; the interpreter's
// handler is put back after.
class StopOnInterrupt {
 public:
  StopOnInterrupt() {
    g_stop_session.store(false);
    struct sigaction action {};
    action.sa_handler = StopSession;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_);
  }
  ~StopOnInterrupt() { sigaction(SIGINT, &previous_, nullptr); }
  StopOnInterrupt(const StopOnInterrupt&) = delete;
  StopOnInterrupt& operator=(const StopOnInterrupt&) = delete;

 private:
  struct sigaction previous_ {};
};

HilSessionResult RunSession(const py::handle& diagram, const std::vector<std::string>& replace,
                            const std::vector<std::string>& set, double duration, const py::handle& out,
                            const std::string& board, int port, double reply_timeout, double connect_timeout,
                            const std::string& quanser_board, const std::string& quanser_id, int encoders,
                            int analog_outputs, double hardware_watchdog, int max_missed, int max_overruns,
                            int fifo_priority, bool lock_memory) {
  if (port < 0 || port > 65535) {
    throw std::invalid_argument(fmt::format("run_hil_session: port {} is not a port: give 1 … 65535", port));
  }
  HilSessionSettings s;
  s.diagram = PathText(diagram);
  s.replacements = replace;
  s.overrides = set;
  s.duration = duration;
  s.out = PathText(out);
  s.board = ParseHilBoardKind(board);
  s.udp.stage_port = static_cast<std::uint16_t>(port);
  s.udp.reply_timeout = reply_timeout;
  s.udp.connect_timeout = connect_timeout;
  s.quanser.board_type = quanser_board;
  s.quanser.board_identifier = quanser_id;
  s.quanser.encoder_channels = encoders;
  s.quanser.analog_outputs = analog_outputs;
  s.quanser.watchdog_timeout = hardware_watchdog;
  s.loop.max_missed_streak = max_missed;
  s.loop.max_overrun_streak = max_overruns;
  s.loop.realtime.fifo_priority = fifo_priority;
  s.loop.realtime.lock_memory = lock_memory;
  StopOnInterrupt interrupt;
  py::gil_scoped_release release;
  return RunHilSession(s, &g_stop_session);
}

std::string SessionRepr(const HilSessionResult& r) {
  std::string metrics;
  for (const auto& [name, value] : r.run.metrics) {
    metrics += fmt::format("{}{} = {:.4g}", metrics.empty() ? "" : ", ", name, value);
  }
  return fmt::format("<HilSessionResult {} on {}: {} ticks, {}{}>", r.name, r.board, r.run.statistics.ticks,
                     r.run.completed ? "completed" : "stopped: " + r.run.stop_reason,
                     metrics.empty() ? "" : "; " + metrics);
}

}  // namespace

void BindHil(py::module_& m) {
  py::class_<HilSessionResult>(m, "HilSessionResult",
                               "What run_hil_session gave: to_dict() is the summary.json it wrote.")
      .def_property_readonly("completed", [](const HilSessionResult& r) { return r.run.completed; },
                             "True when the loop ran to the stop time without a safe stop.")
      .def_property_readonly("stop_reason", [](const HilSessionResult& r) { return r.run.stop_reason; },
                             "Why the loop safe-stopped ('' when completed).")
      .def_property_readonly("metrics", [](const HilSessionResult& r) { return r.run.metrics; },
                             "The diagram's metrics over the run [SI].")
      .def_property_readonly("board", [](const HilSessionResult& r) { return r.board; })
      .def("to_dict", [](const HilSessionResult& r) { return FromJson(r.ToJson()); },
           "summary.json: metrics, metric_units, samples, hil (board, completed, stop_reason, loop statistics [s]).")
      .def("__repr__", &SessionRepr);

  const HilSessionSettings d;
  m.def("run_hil_session", &RunSession, py::arg("diagram"), py::kw_only(), py::arg("replace"),
        py::arg("set") = d.overrides, py::arg("duration") = d.duration, py::arg("out") = d.out.string(),
        py::arg("board") = HilBoardName(d.board), py::arg("port") = int{d.udp.stage_port},
        py::arg("reply_timeout") = d.udp.reply_timeout,
        py::arg("connect_timeout") = d.udp.connect_timeout, py::arg("quanser_board") = d.quanser.board_type,
        py::arg("quanser_id") = d.quanser.board_identifier, py::arg("encoders") = d.quanser.encoder_channels,
        py::arg("analog_outputs") = d.quanser.analog_outputs,
        py::arg("hardware_watchdog") = d.quanser.watchdog_timeout, py::arg("max_missed") = d.loop.max_missed_streak,
        py::arg("max_overruns") = d.loop.max_overrun_streak,
        py::arg("fifo_priority") = d.loop.realtime.fifo_priority,
        py::arg("lock_memory") = d.loop.realtime.lock_memory,
        "Hardware in the loop as `motionblocks hil`: swaps subsystems of `diagram` (a path) for `replace` "
        "('ELEMENT=FILE', e.g. 'plant=diagrams/hil/subsystems/hil_io.json'), applies `set` ('block.param=value'), "
        "runs it in real time for `duration` s (0: the diagram's stop time) against `board` — 'udp': "
        "`motionblocks virtual-stage` on 127.0.0.1:`port` (reply_timeout, connect_timeout in s), or 'quanser' "
        "(quanser_board, quanser_id, encoders, analog_outputs, hardware_watchdog in s) — and writes signals.csv, "
        "timing.csv and summary.json into `out` (an earlier run's removed first). Safe stop after `max_missed` "
        "missed samples or `max_overruns` overruns in a row, or on Ctrl-C: the result then says completed False. "
        "Raises ValueError for bad settings, RuntimeError when the board cannot be started (e.g. no stage answers).");
}

}  // namespace mb::python
