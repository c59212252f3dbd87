// motionblocks: block-diagram simulation for precision motion control. One top-level catch: every error
// reaches the user as one clear message and a non-zero exit code (README "Exit codes"): 0 ok, 1 failure,
// 2 bad usage or bad input, 3 numerical failure.

#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "engine/execution_order.h"
#include "engine/file_access.h"
#include "engine/input_file.h"
#include "engine/numerical_error.h"
#include "engine/output_file.h"
#include "engine/terminal_text.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/report.h"
#include "tools/workflow/error_text.h"

namespace {

constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitNumericalFailure = 3;
constexpr std::size_t kMaxPlotsCeiling = 100000;  // --max-plots: one gnuplot each, ~0.1 s

// One message (reworded if a library's, cut if long: tools/workflow/error_text.h) and the exit code.
int ReportError(const CLI::App& app, const std::exception& e, int code) {
  std::cerr << "motionblocks: error: " << mb::ErrorText(e, mb::CommandInputs(app)) << "\n";
  return code;
}

// Standard output and error through ControlEscapingBuffer while it lives: ESC, BEL, CR … from a diagram, a log or a
// file name reach the terminal as visible escapes, in every message and every line a command prints (issue 30).
class EscapedTerminalOutput {
 public:
  EscapedTerminalOutput() {
    std::cout.rdbuf(&out_);
    std::cerr.rdbuf(&err_);
  }
  EscapedTerminalOutput(const EscapedTerminalOutput&) = delete;
  EscapedTerminalOutput& operator=(const EscapedTerminalOutput&) = delete;
  ~EscapedTerminalOutput() {
    std::cout.flush();
    std::cerr.flush();
    std::cout.rdbuf(out_target_);
    std::cerr.rdbuf(err_target_);
  }

 private:
  std::streambuf* out_target_ = std::cout.rdbuf();
  std::streambuf* err_target_ = std::cerr.rdbuf();
  mb::ControlEscapingBuffer out_{out_target_};
  mb::ControlEscapingBuffer err_{err_target_};
};

}  // namespace

int main(int argc, char** argv) {
  const EscapedTerminalOutput escaped_output;
  mb::RemoveTemporaryFilesOnInterrupt();  // Ctrl-C leaves no half-written "<file>.tmp<pid>" (issue 41)
  CLI::App app{"motionblocks — block-diagram simulation, model-vs-measurement diagnosis and learned disturbance "
               "compensation for precision motion control"};
  app.set_version_flag("--version", std::string("motionblocks ") + MB_VERSION);
  app.require_subcommand(1);
  app.fallthrough();  // global options may follow the subcommand
  app.add_option_function<std::vector<std::string>>(
         "--allow-path",
         [](const std::vector<std::string>& folders) {
           for (const auto& folder : folders) mb::AllowDiagramFilesUnder(folder);
         },
         "A folder outside the diagram's own whose files the diagram's file parameters (from_file.file, gpr.model, "
         "subsystem diagram) may read; repeat for several")
      ->type_name("DIR")
      ->allow_extra_args(false);
  app.add_option_function<double>(
         "--max-input-mb",
         [](double megabytes) {
           if (!(megabytes >= 1e-6 && megabytes <= 1e9)) {  // NaN fails too
             throw CLI::ValidationError("--max-input-mb", "the input size limit must lie in [1e-6, 1e9] MB");
           }
           mb::SetMaxInputFileBytes(static_cast<std::uintmax_t>(megabytes * 1e6));
         },
         "Largest input file read (diagram, measurement log, table, GP model, sweep file), in MB (default 1074, "
         "1 GiB); devices and FIFOs are never read")
      ->type_name("MB")
      ->allow_extra_args(false);
  app.add_option_function<std::size_t>(
         "--max-plots",
         [](std::size_t count) {
           if (count < 1 || count > kMaxPlotsCeiling) {
             throw CLI::ValidationError("--max-plots", fmt::format("give a figure count from 1 to {}", kMaxPlotsCeiling));
           }
           mb::SetMaxReportFigures(count);
         },
         fmt::format("Most figures one report draws (default {}; at most {}): a run logging more signals plots the "
                     "first N and lists the rest by name in report.html",
                     mb::kDefaultMaxReportFigures, kMaxPlotsCeiling))
      ->type_name("N")
      ->allow_extra_args(false);
  mb::AddRegisteredCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;  // --help prints and exits 0
  } catch (const mb::NumericalError& e) {
    return ReportError(app, e, kExitNumericalFailure);
  } catch (const mb::DiagramError& e) {
    return ReportError(app, e, kExitBadInput);
  } catch (const mb::AlgebraicLoopError& e) {
    return ReportError(app, e, kExitBadInput);
  } catch (const std::invalid_argument& e) {
    return ReportError(app, e, kExitBadInput);
  } catch (const nlohmann::json::exception& e) {  // a JSON input of the wrong shape that no check caught
    return ReportError(app, e, kExitBadInput);
  } catch (const std::exception& e) {  // filesystem errors, bad_alloc, Boost.Math's: reworded
    return ReportError(app, e, mb::IsLibraryNumericalError(e) ? kExitNumericalFailure : kExitFailure);
  }
  return 0;
}
