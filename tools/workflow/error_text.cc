#include "tools/workflow/error_text.h"

#include <algorithm>
#include <cctype>
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

// The residual's whiteness test (Ljung–Box, models/diagnosis/signal_processing.cc) fails on a residual that is not
// finite or overflows (a measured column near 1e300): named by its meaning, not by the function or Boost's text.
constexpr std::string_view kWhitenessCheck = "ResidualAutocorrelation: ";
constexpr std::string_view kBoostChiSquare = "Chi Square";

std::string WhitenessErrorText(const std::string& what, const std::vector<std::string>& inputs) {
  return fmt::format("the residual between the model and the measurement is no usable signal{}: its whiteness test "
                     "(Ljung–Box) found {}. Check the measured column's values and unit (values near 1e300 overflow) "
                     "and that the model's output is finite along the record",
                     Reading(inputs), Excerpt(what));
}

// The length of a leading "FunctionName: " or "Class::Method: " (CamelCase, at least two capitals), else 0: an
// internal check whose message names a function the user never called.
std::size_t InternalCheckPrefix(std::string_view text) {
  std::size_t i = 0, capitals = 0;
  const auto identifier = [&] {
    const std::size_t start = i;
    while (i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) != 0 || text[i] == '_')) {
      if (std::isupper(static_cast<unsigned char>(text[i])) != 0) ++capitals;
      ++i;
    }
    return i > start && std::isupper(static_cast<unsigned char>(text[start])) != 0;
  };
  if (!identifier()) return 0;
  if (text.substr(i, 2) == "::") {
    i += 2;
    if (!identifier()) return 0;
  }
  const bool lower_seen = std::any_of(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(i),
                                      [](char c) { return std::islower(static_cast<unsigned char>(c)) != 0; });
  return capitals >= 2 && lower_seen && text.substr(i, 2) == ": " ? i + 2 : 0;
}

std::string InternalCheckErrorText(const std::string& text, std::size_t prefix, const std::vector<std::string>& inputs) {
  return fmt::format("internal check {} failed{}: {}. The inputs led to a case the program does not handle: check "
                     "their values and units (a column in mm read as m, values near 1e300, a column that does not "
                     "vary), and report it with the input files if they look right",
                     text.substr(0, prefix - 2), Reading(inputs), text.substr(prefix));
}

}  // namespace

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
    const std::string what = e.what();
    const auto colon = what.find(": ", kBoostMathPrefix.size());
    text = what.find(kBoostChiSquare) != std::string::npos && colon != std::string::npos
               ? WhitenessErrorText(what.substr(colon + 2), inputs)
               : BoostMathErrorText(what, inputs);
  } else {
    text = e.what();
    if (text.rfind(kWhitenessCheck, 0) == 0) {
      text = WhitenessErrorText(text.substr(kWhitenessCheck.size()), inputs);
    } else if (const std::size_t prefix = InternalCheckPrefix(text); prefix > 0) {
      text = InternalCheckErrorText(text, prefix, inputs);
    }
  }
  return Excerpt(text, kMaxErrorMessage);
}

}  // namespace mb
