#include "tools/commands/error_text.h"

#include <filesystem>
#include <new>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "engine/text_excerpt.h"

namespace mb {

namespace {

constexpr std::string_view kBoostMathPrefix = "Error in function boost::";

// " (reading a.json, b.csv)", or "" without inputs.
std::string Reading(const std::vector<std::string>& inputs) {
  std::vector<std::string> names;
  for (const auto& input : inputs) names.push_back(Excerpt(input));
  return names.empty() ? "" : fmt::format(" (reading {})", fmt::join(names, ", "));
}

std::string JsonContentErrorText(const nlohmann::json::exception& e, const std::vector<std::string>& inputs) {
  return fmt::format("unexpected JSON content{}: {}. Check the file: a diagram against `motionblocks schema`, a "
                     "sweep against `motionblocks schema --sweep`, a GP model as written by `motionblocks fit-gpr`",
                     Reading(inputs), JsonErrorText(e));
}

std::string FilesystemErrorText(const std::filesystem::filesystem_error& e, const std::vector<std::string>& inputs) {
  std::string paths = e.path1().empty() ? "" : " " + Excerpt(e.path1().string());
  if (!e.path2().empty()) paths += " → " + Excerpt(e.path2().string());
  return fmt::format("cannot use the file or folder{}{}: {}. Check that the path exists, is a folder where one is "
                     "expected, and that you may read and write there (--out DIR chooses another output folder)",
                     paths, Reading(inputs), e.code().message());
}

std::string BoostMathErrorText(const std::string& text, const std::vector<std::string>& inputs) {
  const auto colon = text.find(": ", kBoostMathPrefix.size());
  const std::string what = colon == std::string::npos ? text : text.substr(colon + 2);
  return fmt::format("a numerical routine failed{}: {}. A parameter is probably far out of range (a length scale, "
                     "period or variance many orders from the data's): check the model's and the diagram's values",
                     Reading(inputs), Excerpt(what));
}

}  // namespace

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

bool IsLibraryNumericalError(const std::exception& e) {
  return std::string_view(e.what()).substr(0, kBoostMathPrefix.size()) == kBoostMathPrefix;
}

std::string ErrorText(const std::exception& e, const std::vector<std::string>& inputs) {
  std::string text;
  if (const auto* json_error = dynamic_cast<const nlohmann::json::exception*>(&e)) {
    text = JsonContentErrorText(*json_error, inputs);
  } else if (const auto* fs_error = dynamic_cast<const std::filesystem::filesystem_error*>(&e)) {
    text = FilesystemErrorText(*fs_error, inputs);
  } else if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) {
    text = fmt::format("out of memory{}. The input or the run is too large for this machine: shorten the run or "
                       "lower --max-steps / --max-runs, log fewer signals, or cut the measurement log",
                       Reading(inputs));
  } else if (IsLibraryNumericalError(e)) {
    text = BoostMathErrorText(e.what(), inputs);
  } else {
    text = e.what();
  }
  return Excerpt(text, kMaxErrorMessage);
}

}  // namespace mb
