// The options several subcommands share (cli_options.h). --max-steps N on every command that simulates: raises
// (or lowers) the run-length limit that Simulator checks before a run (engine/simulator.h SimulationLimits), for
// every simulation the command starts.

#include "tools/commands/cli_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "engine/simulator.h"
#include "engine/text_excerpt.h"
#include "tools/report/progress.h"

namespace mb {

std::vector<std::string> CommandInputs(const CLI::App& app) {
  std::vector<std::string> inputs;
  for (const CLI::App* command : app.get_subcommands()) {
    for (const CLI::Option* option : command->get_options()) {
      const bool input = option->get_positional() || option->check_lname("measurement") ||
                         option->check_lname("validation");
      if (!input) continue;
      for (const auto& value : option->results()) inputs.push_back(value);
    }
  }
  return inputs;
}

void AddMaxStepsOption(CLI::App* command) {
  command
      ->add_option_function<double>(
          "--max-steps",
          [](const double& n) {
            SimulationLimits limits = DefaultSimulationLimits();
            limits.max_steps = n;
            SetDefaultSimulationLimits(limits);
          },
          fmt::format("refuse a simulation estimated to take more steps, or to log more values, than N (default "
                      "{:.0e}; protects against a stopTime or step typo that would run for hours or exhaust memory)",
                      SimulationLimits{}.max_steps))
      ->type_name("N");  // the range (finite, [1, 1e13]) is SetDefaultSimulationLimits' check: NaN and inf too
}

void AddFifoOption(CLI::App* command, int* priority) {
  command->add_option("--fifo", *priority, "SCHED_FIFO priority 1–99 (0 = default scheduler)")
      ->check(CLI::Range(0, 99));
}

CLI::Validator FiniteRange(double low, double high, bool low_open) {
  const std::string range = fmt::format("{}{}, {}]", low_open ? "(" : "[", low, high);
  return CLI::Validator(
      [low, high, low_open, range](std::string& text) -> std::string {
        double value = 0.0;
        const bool number = CLI::detail::lexical_cast(text, value);
        const bool inside = number && std::isfinite(value) && (low_open ? value > low : value >= low) && value <= high;
        return inside ? std::string() : fmt::format("{} is not a number in {}", text, range);
      },
      "NUMBER in " + range);
}

std::function<std::string(const std::string&)> NonEmpty(std::string what) {
  return [what = std::move(what)](const std::string& value) {
    return value.empty() ? fmt::format("an empty value: {}", what) : std::string();
  };
}

std::function<std::string(const std::string&)> WholeNumberText(std::size_t max_digits) {
  return [max_digits](const std::string& text) {
    const bool digits = !text.empty() && text.size() <= max_digits &&
                        std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
    return digits ? std::string() : fmt::format("give a whole number from 0 to {}", std::string(max_digits, '9'));
  };
}

namespace {

void PrintDeprecationNote(const std::string& old_name, const std::string& new_name) {
  std::cerr << fmt::format("motionblocks: note: {} is the old name of {}; it still works, but write {}\n", old_name,
                           new_name, new_name);
}

}  // namespace

void AddDeprecatedAlias(CLI::App* command, const std::string& old_name, const std::string& new_name,
                        std::string* target) {
  command
      ->add_option_function<std::string>(
          old_name,
          [=](const std::string& value) {
            PrintDeprecationNote(old_name, new_name);
            *target = value;
          },
          "deprecated: " + new_name)
      ->group("");
}

void AddDeprecatedAlias(CLI::App* command, const std::string& old_name, const std::string& new_name,
                        std::vector<std::string>* target) {
  command
      ->add_option_function<std::vector<std::string>>(
          old_name,
          [=](const std::vector<std::string>& values) {
            PrintDeprecationNote(old_name, new_name);
            target->insert(target->end(), values.begin(), values.end());
          },
          "deprecated: " + new_name)
      ->group("");
}

std::filesystem::path ShippedDataFolder() {
  namespace fs = std::filesystem;
  if (const char* folder = std::getenv("MOTIONBLOCKS_DATA"); folder != nullptr && *folder != '\0') return folder;
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path installed = (exe.parent_path() / ".." / "share" / "motionblocks").lexically_normal();
    if (fs::is_directory(installed / "diagrams", error)) return installed;
  }
  return MB_DATA_DIR;
}

void AddProgressOptions(CLI::App* command) {
  auto* progress = command->add_flag_callback(
      "--progress", [] { SetProgressMode(ProgressMode::kAlways); },
      "show progress on stderr even when it is not a terminal (a log file, CI)");
  auto* quiet = command->add_flag_callback(
      "--quiet", [] { SetProgressMode(ProgressMode::kNever); }, "no progress and no stage lines on stderr");
  progress->excludes(quiet);
}

CLI::Option* AddSetOption(CLI::App* command, std::vector<std::string>* overrides, const std::string& help) {
  return command->add_option("--set", *overrides, help + ". " + std::string(kSetUnitRule))->type_name("BLOCK.PARAM=VALUE");
}

std::vector<ParameterOverride> ParseOverrides(const std::vector<std::string>& sets) {
  std::vector<ParameterOverride> overrides;
  for (const auto& s : sets) overrides.push_back(ParameterOverride::Parse(s));
  return overrides;
}

nlohmann::json ReadDiagramWithOverrides(const std::string& path, const std::vector<std::string>& sets) {
  const std::vector<ParameterOverride> overrides = ParseOverrides(sets);
  nlohmann::json diagram = ReadDiagramJson(path);
  ApplyOverrides(&diagram, overrides, path);
  return diagram;
}

std::map<std::string, std::string> ParseColumnMap(const std::vector<std::string>& maps) {
  std::map<std::string, std::string> column_map;
  for (const auto& m : maps) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) {
      throw std::invalid_argument(fmt::format("--map '{}': write connector=column", Excerpt(m)));
    }
    column_map[m.substr(0, eq)] = m.substr(eq + 1);
  }
  return column_map;
}

std::map<std::string, double> ParseInputValues(const std::vector<std::string>& inputs) {
  std::map<std::string, double> values;
  for (const auto& in : inputs) {
    const auto eq = in.find('=');
    const std::string number = eq == std::string::npos ? std::string() : in.substr(eq + 1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), value);
    if (eq == std::string::npos || eq == 0 || number.empty() || error != std::errc() ||
        end != number.data() + number.size() || !std::isfinite(value)) {
      throw std::invalid_argument(fmt::format("--input '{}': write connector=number (a finite number in the "
                                              "connector's unit), e.g. --input velocity=0.1", Excerpt(in)));
    }
    values[in.substr(0, eq)] = value;
  }
  return values;
}

std::vector<std::string> SplitCommaLists(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const auto& item : items) {
    std::size_t start = 0;
    while (start <= item.size()) {
      const auto comma = item.find(',', start);
      const std::string name = item.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!name.empty()) out.push_back(name);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return out;
}

MeasurementSettings MeasurementOptions::Settings() const {
  MeasurementSettings settings{ParseColumnMap(maps), position_column, derivative_cutoff_hz, ParseIntersample(intersample)};
  settings.every_pair = every_pair;
  return settings;
}

void AddMeasurementOptions(CLI::App* command, MeasurementOptions* options, const std::string& measurement_help,
                           const std::string& set_help) {
  command->add_option("--measurement", options->measurement, measurement_help)
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--map", options->maps, "connector=column: read a connector from another column (repeatable)");
  AddSetOption(command, &options->overrides, set_help);
  command->add_option("--position-column", options->position_column, "measured position column [m, rad, rev or deg: the unit is the name's suffix]")
      ->capture_default_str();
  command->add_option("--derivative-cutoff-hz", options->derivative_cutoff_hz,
                      "zero-phase low-pass cut-off before differentiating the position [Hz]")
      ->capture_default_str();
  command->add_option("--intersample", options->intersample,
                      "the measured outputs between samples (equation-error diagrams): foh = a sample is the value at "
                      "its instant (a sensor), zoh = a sample is held until the next (a logged command, e.g. a force "
                      "or current reference): compared half a sample later")
      ->check(CLI::IsMember({"foh", "zoh"}))
      ->capture_default_str();
  command->add_flag("--every-pair", options->every_pair,
                    "the diagnosis proposes every product of its grammar (multiplier × modulator, docs/diagnosis.md), "
                    "not only the products the catalogue named before it");
}

}  // namespace mb
