#pragma once
// pd_controller: the paper's feedback controller C_FB = K_p + K_d s (eq. 3), with the derivative filtered by a
// first-order low-pass so that it is proper: C(s) = K_p + K_d s/(T_f s + 1).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// u = C{e}, C(s) = K_p + K_d·s/(T_f s + 1) (paper eq. 3 with a derivative filter of time constant T_f).
/// Ports: in "e" (the tracking error r − x, feeds through), out "u". Parameters: kp K_p, kd K_d (unit free;
/// N/m and N·s/m in a position loop with force output), derivative_filter T_f [s] ≥ 0 (default 1e-3),
/// method "backward_euler" (default) or "tustin" (discrete only).
/// Continuous (no sampleTime): state z, T_f ż = e − z, u = K_p e + K_d (e − z)/T_f, z(0) = 0 (so a non-zero
/// e(0) gives the derivative kick K_d e(0)/T_f, as Simulink's PID does); T_f > 0 required.
/// Discrete (sampleTime [Ts, offset]): the filtered derivative d[k] discretised with
///  - backward Euler, s ← (1 − z⁻¹)/Ts: d[k] = (T_f d[k−1] + K_d (e[k] − e[k−1]))/(T_f + Ts); stable for every
///    T_f ≥ 0, T_f = 0 gives the plain backward difference K_d (e[k] − e[k−1])/Ts;
///  - Tustin, s ← (2/Ts)(1 − z⁻¹)/(1 + z⁻¹): d[k] = ((2T_f − Ts) d[k−1] + 2K_d (e[k] − e[k−1]))/(2T_f + Ts);
///    needs T_f > 0 (at T_f = 0 its pole sits at z = −1);
/// u[k] = K_p e[k] + d[k], e[−1] = d[−1] = 0 (Åström & Hägglund, Advanced PID Control, 2006, §13.5).
/// @throws std::invalid_argument for T_f = 0 in the continuous or Tustin form, an unknown method, or a method
/// other than the default without a sampleTime.
class PdController final : public Block {
 public:
  explicit PdController(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  /// d[k] from e[k] and the stored e[k−1], d[k−1] (discrete form).
  double FilteredDerivative(const BlockContext& context) const;

  double kp_;
  double kd_;
  double filter_;  // T_f [s]
  bool discrete_ = false;
  // d[k] = a·d[k−1] + b·(e[k] − e[k−1]) in the discrete form.
  double a_ = 0.0;
  double b_ = 0.0;
};

}  // namespace mb
