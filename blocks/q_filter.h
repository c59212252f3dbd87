#pragma once
// q_filter: the binomial Q-filter of the disturbance observer (paper eq. 5),
//   Q(s) = ω_q^{n_r}/(s + ω_q)^{n_r},  ω_q = 2π·cutoff_hz,
// continuous (no sampleTime) or discretised at sampleTime [Ts, offset] by zero-order hold ("zoh", default:
// exact for a held input, strictly proper, so u does not feed through) or Tustin ("tustin": biproper, u feeds
// through). Starts at rest (zero state).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/stability/lti.h"

namespace mb {

/// y = Q{u}. Ports: in "u", out "y" (width 1, any unit). Parameters: cutoff_hz [Hz] > 0, relative_degree n_r
/// (1…8), discretization ("zoh" | "tustin", used only with a sampleTime). Continuous form: n_r states in
/// controllable canonical form. @throws std::invalid_argument for a bad cut-off or discretization name.
class QFilter final : public Block {
 public:
  explicit QFilter(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

  bool is_discrete() const { return discrete_; }
  /// The discrete filter (valid when is_discrete()).
  const DiscreteTf& discrete_filter() const { return filter_; }

 private:
  bool discrete_;
  DiscreteTf filter_;
  ContinuousSs realization_;
};

}  // namespace mb
