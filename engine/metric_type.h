#pragma once
// The figures of merit a diagram's "metrics" compute after a run (summary.json's "metrics"). The names are the file
// format's and this table is the one place they are written: the schema's enum, the reader and the evaluation come
// from it, so an unknown type is a load error and every known one has a value.

#include <array>
#include <optional>
#include <string_view>

namespace mb {

enum class MetricType {
  kRmse,          ///< sqrt(mean(s²)) over the window
  kMaxAbs,        ///< max |s|
  kMean,          ///< mean(s)
  kFinal,         ///< s at the last logged instant of the window
  kRmsDifference  ///< sqrt(mean((s − reference)²))
};

/// The file format's names, in the enum's order.
inline constexpr std::array<std::string_view, 5> kMetricTypeNames{"rmse", "max_abs", "mean", "final",
                                                                  "rms_difference"};

inline std::string_view Name(MetricType type) { return kMetricTypeNames[static_cast<std::size_t>(type)]; }

/// The type a name stands for; nullopt for any other text.
inline std::optional<MetricType> MetricTypeNamed(std::string_view name) {
  for (std::size_t i = 0; i < kMetricTypeNames.size(); ++i) {
    if (name == kMetricTypeNames[i]) return static_cast<MetricType>(i);
  }
  return std::nullopt;
}

}  // namespace mb
