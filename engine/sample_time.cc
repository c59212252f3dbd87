#include "engine/sample_time.h"

#include <stdexcept>

#include <fmt/format.h>

namespace mb {

namespace {
constexpr double kHitTolerance = 1e-9;  // relative to the period
}

SampleTime SampleTime::Discrete(double period, double offset) {
  if (!(period > 0.0) || !std::isfinite(period)) {
    throw std::invalid_argument(fmt::format("sample time period must be > 0 s, got {}", period));
  }
  if (!(offset >= 0.0) || !(offset < period)) {
    throw std::invalid_argument(
        fmt::format("sample time offset must satisfy 0 <= offset < period ({} s), got {}", period, offset));
  }
  return {Kind::kDiscrete, period, offset};
}

long long SampleTime::FirstHitIndexAtOrAfter(double t) const {
  const double k = (t - offset) / period;
  const double k_ceil = std::ceil(k - kHitTolerance);
  return k_ceil < 0.0 ? 0 : static_cast<long long>(k_ceil);
}

bool SampleTime::IsHit(double t) const {
  if (kind != Kind::kDiscrete) return false;
  const double k = (t - offset) / period;
  return k > -kHitTolerance && std::abs(k - std::round(k)) < kHitTolerance;
}

std::string SampleTime::ToString() const {
  switch (kind) {
    case Kind::kContinuous: return "continuous";
    case Kind::kInherited: return "inherited";
    case Kind::kConstant: return "constant";
    case Kind::kDiscrete: return fmt::format("discrete [{}, {}]", period, offset);
  }
  return "unknown";
}

}  // namespace mb
