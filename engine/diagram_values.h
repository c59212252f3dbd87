#pragma once
// Reading one value of a diagram's JSON for the diagram builder (diagram_builder.cc): a wrong value appends a
// problem ("<json pointer>: …") to the list instead of throwing, so that the user sees every problem at once.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/sample_time.h"

namespace mb {

/// j[key] as a number, `fallback` when j has no `key`; a problem (at ptr/key) and `fallback` when it is not a
/// number.
double NumberOr(const nlohmann::json& j, const char* key, double fallback, const std::string& ptr,
                std::vector<std::string>* problems);

/// An element's "sampleTime": Ts or [Ts, offset] in seconds, a discrete sample time; a problem (at ptr) and
/// nullopt for any other value or one SampleTime::Discrete refuses.
std::optional<SampleTime> ParseSampleTime(const nlohmann::json& j, const std::string& ptr,
                                          std::vector<std::string>* problems);

}  // namespace mb
