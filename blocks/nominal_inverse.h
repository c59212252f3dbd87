#pragma once
// nominal_inverse: the inverse of the nominal plant P_n = 1/(M_n s² + B_n s) (paper eq. 4), which is improper on
// its own; two proper forms:
//  * form "derivatives" (C_FF of eq. 4, the feedforward on the reference): y = M_n·a + B_n·v from the
//    reference's velocity v and acceleration a — exactly P_n⁻¹{x_d} for a smooth reference. Static, both
//    inputs feed through; inherits its sample time unless one is given.
//  * form "filtered" (Q∘P_n⁻¹ of eq. 51): y = ω^n (M_n s² + B_n s)/(s + ω)^n {x}, continuous without sampleTime
//    or discretised by "tustin" (default) or "zoh" with one. The filter starts at rest at the first input
//    (the stage has stood still at x(0)), so an initial position gives no transient (discrete form; the
//    continuous form starts at rest at x = 0).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/stability/lti.h"

namespace mb {

/// Ports, form "derivatives": in "velocity" [m/s], "acceleration" [m/s²]; form "filtered": in "x" [m]; both
/// out "y" [N]. Parameters: nominal_mass M_n [kg], nominal_damping B_n [N·s/m], form, cutoff_hz and
/// relative_degree of Q (form "filtered"), discretization. @throws std::invalid_argument for an unknown form,
/// n_r < 2 in form "filtered", or a bad cut-off.
class NominalInverse final : public Block {
 public:
  explicit NominalInverse(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  enum class Form { kDerivatives, kFiltered };
  Form form_;
  double nominal_mass_;
  double nominal_damping_;
  bool discrete_ = false;
  DiscreteTf filter_;        // form "filtered", discrete
  ContinuousSs realization_; // form "filtered", continuous
};

}  // namespace mb
