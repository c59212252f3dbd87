#include "models/diagnosis/command_limit.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/diagnosis/robust_weighting.h"

namespace mb {
namespace {

constexpr double kExcessNoise = 3.0;  // robust noise levels the log must exceed the acted force by, beyond a limit

}  // namespace

std::pair<double, double> LimitScanRange(const Eigen::VectorXd& values) {
  std::vector<double> magnitude(values.data(), values.data() + values.size());
  for (double& m : magnitude) m = std::abs(m);
  std::sort(magnitude.begin(), magnitude.end());
  const auto n = magnitude.size();
  return {magnitude[n / 2], magnitude[n - 1 - static_cast<std::size_t>(kMinShareBeyondLimit * static_cast<double>(n))]};
}

bool LogExceedsActedForce(const Eigen::VectorXd& residual, double side,
                          const std::function<bool(Eigen::Index)>& beyond) {
  std::vector<double> excess;
  for (Eigen::Index i = 0; i < residual.size(); ++i) {
    if (beyond(i)) excess.push_back(side * residual(i));
  }
  if (excess.empty() ||
      static_cast<double>(excess.size()) < kMinShareBeyondLimit * static_cast<double>(residual.size())) {
    return false;
  }
  const auto middle = excess.begin() + static_cast<std::ptrdiff_t>(excess.size() / 2);
  std::nth_element(excess.begin(), middle, excess.end());
  return *middle >= kExcessNoise * diagnosis_detail::RobustScale(residual);
}

}  // namespace mb
