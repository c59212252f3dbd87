#pragma once
// The options several `motionblocks` subcommands share, declared and parsed in one place: --set overrides,
// --map connector=column, comma lists ("block.param,…"), the measurement options of compare, fit and improve
// (--measurement, --map, --set, --position-column, --derivative-cutoff-hz), --max-steps, --fifo (hil and
// virtual-stage), and the checks of a non-empty value and of a whole number's text.

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "tools/workflow/measurement.h"

namespace mb {

/// The input files of the subcommand `app` ran: its positional arguments and --measurement/--validation values
/// (named in error messages: tools/workflow/error_text.h).
std::vector<std::string> CommandInputs(const CLI::App& app);

// Option names, one per meaning across the commands (README "Command-line conventions"): --out DIR for an output
// folder, -o/--output FILE for one output file, --fit block.param,… for the parameters to refit, --position-column /
// --velocity-column / --disturbance-column for the columns of a table, -j/--jobs N, --quiet and --progress.

/// Keeps an old option spelling working: `old_name` (hidden from --help) stores into `target` like `new_name`,
/// and prints one line on stderr: "motionblocks: note: --params is the old name of --fit; it still works, but
/// write --fit". A list (repeatable option) appends to what `new_name` collected.
void AddDeprecatedAlias(CLI::App* command, const std::string& old_name, const std::string& new_name,
                        std::string* target);
void AddDeprecatedAlias(CLI::App* command, const std::string& old_name, const std::string& new_name,
                        std::vector<std::string>* target);

/// The folder holding the shipped data (its diagrams/ folder), found without the working directory: $MOTIONBLOCKS_DATA
/// if set, else <the executable's folder>/../share/motionblocks when installed (`cmake --install`), else the folder
/// the build was configured with (MB_DATA_DIR, the source tree).
std::filesystem::path ShippedDataFolder();

/// Adds --progress (progress on stderr also when it is not a terminal) and --quiet (no progress and no stage lines)
/// to a long-running subcommand; they set the process-wide ProgressMode (tools/report/progress.h).
void AddProgressOptions(CLI::App* command);

/// A CLI11 check that a number is finite and lies in [low, high] (or (low, high] with `low_open`): NaN and ±inf are
/// refused, which CLI::Range and CLI::PositiveNumber let through. Refused at parse time: exit 2, "--duration: nan is
/// not a number in (0, 86400]".
CLI::Validator FiniteRange(double low, double high, bool low_open = false);

/// A CLI11 check that refuses an empty value ("an empty value: <what>"), e.g. `--shard ''`, which would otherwise
/// count as not given.
std::function<std::string(const std::string&)> NonEmpty(std::string what);

/// A CLI11 check on the raw text of a whole number of at most `max_digits` digits (a number that overflows would be
/// read as 2^64 − 1): "give a whole number from 0 to 99…9" otherwise.
std::function<std::string(const std::string&)> WholeNumberText(std::size_t max_digits);

/// Adds --fifo PRIO (SCHED_FIFO priority 1–99, 0 = the default scheduler; hw/realtime.h RealTimeOptions) to a
/// command that runs a real-time loop, stored into `priority`.
void AddFifoOption(CLI::App* command, int* priority);

/// Adds --max-steps N (SimulationLimits::max_steps for every simulation the command runs) to a subcommand.
void AddMaxStepsOption(CLI::App* command);

/// How --set reads a value (the one meaning of a number, engine/parameters.h ReplacedParameterSlot); every --set help
/// ends with it.
inline constexpr const char* kSetUnitRule =
    "A number is in the parameter's SI unit (kg, m, N*s/m, as `motionblocks blocks TYPE` lists), whatever unit the "
    "diagram wrote it in; or give a quantity: --set 'mass.mass={\"value\": 2000, \"unit\": \"g\"}'";

/// Adds --set block.param=value (repeatable) to `command`, collected into `overrides`; `help` is the option's text,
/// kSetUnitRule is appended.
CLI::Option* AddSetOption(CLI::App* command, std::vector<std::string>* overrides,
                          const std::string& help = "parameter override block.param=value (repeatable)");

/// Parses every --set value. @throws std::invalid_argument as ParameterOverride::Parse (naming the bad one).
std::vector<ParameterOverride> ParseOverrides(const std::vector<std::string>& sets);

/// Reads a diagram's JSON and applies the --set values to it. @throws as ReadDiagramJson and ApplyOverrides.
nlohmann::json ReadDiagramWithOverrides(const std::string& path, const std::vector<std::string>& sets);

/// Parses --map values "connector=column" into connector → column. @throws std::invalid_argument
/// "--map 'x': write connector=column" for a value without '='.
std::map<std::string, std::string> ParseColumnMap(const std::vector<std::string>& maps);

/// Parses --input values "connector=value" (a finite number in the connector's unit) into connector → value.
/// @throws std::invalid_argument "--input 'x=abc': write connector=number" for a value without '=' or a number.
std::map<std::string, double> ParseInputValues(const std::vector<std::string>& inputs);

/// Splits comma lists ("a,b", "c" → a, b, c); empty items are dropped.
std::vector<std::string> SplitCommaLists(const std::vector<std::string>& items);

/// How compare, fit and improve read a measurement (--measurement, --map, --set, --position-column,
/// --derivative-cutoff-hz, --intersample, --every-pair).
struct MeasurementOptions {
  std::string measurement;                    ///< the measurement log CSV (time_s first)
  std::vector<std::string> maps;              ///< --map connector=column
  std::vector<std::string> overrides;         ///< --set block.param=value
  // The defaults are MeasurementSettings' (the only ones; the Python module takes them from there too).
  std::string position_column = MeasurementSettings{}.position_column;
  double derivative_cutoff_hz = MeasurementSettings{}.derivative_cutoff_hz;
  std::string intersample = IntersampleName(MeasurementSettings{}.intersample);  ///< --intersample foh|zoh
  bool every_pair = MeasurementSettings{}.every_pair;  ///< --every-pair: the diagnosis' whole grammar
  /// The --map, --position-column, --derivative-cutoff-hz, --intersample and --every-pair values as the workflow takes
  /// them.
  /// @throws std::invalid_argument as ParseColumnMap.
  MeasurementSettings Settings() const;
};

/// Declares the MeasurementOptions on `command` (--measurement required, an existing file; `measurement_help`
/// its text; `set_help` the --set text).
void AddMeasurementOptions(CLI::App* command, MeasurementOptions* options, const std::string& measurement_help,
                           const std::string& set_help = "parameter override block.param=value (repeatable)");

}  // namespace mb
