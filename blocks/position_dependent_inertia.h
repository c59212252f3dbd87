#pragma once
// position_dependent_inertia: the force of a moving mass that varies periodically with the position — an arm whose
// inertia changes with its angle, a linkage or a cam whose lever changes along the travel. With the kinetic energy
// T = ½M(x)·v², Lagrange's equation d/dt(∂T/∂v) − ∂T/∂x gives the force
//   y = M(x)·a + ½M′(x)·v²,  M(x) = Σ_{h=1..H} a_h cos(2πh(x − x₀)/P) + b_h sin(2πh(x − x₀)/P)
// (Goldstein, Classical Mechanics, 3rd ed., §1.4): the v² term is the kinetic energy the mass's change takes up or
// gives back, often larger than the M(x)·a term at speed. M(x) is the part of the mass that varies (the constant part
// is the model's mass). The diagnosis' inertia_ripple (models/diagnosis/effects/factor_products.cc, the same columns:
// InertiaColumns) adds it; its coefficients are usually fitted.

#include "engine/block.h"
#include "engine/registry.h"
#include "models/physics/fourier_series.h"

namespace mb {

/// Ports: in "x" [m], in "v" [m/s], in "a" [m/s²]; out "y" [N] (coefficients in kg), out "mass" M(x) [kg].
/// Parameters: period P [m] > 0, harmonics H ≥ 1, cos_coefficients a_1…a_H and sin_coefficients b_1…b_H [kg] (empty
/// = zeros), position_offset x₀ [m] (default 0), acceleration_input (default true; false: no input "a" and
/// y = ½M′(x)·v² — in a simulated loop the plant takes M(x) from "mass" on its mass input, blocks/rigid_body.h, since
/// a block of the plant's own acceleration would close an algebraic loop). Inherited sample time; x, v and a feed
/// through.
/// @throws std::invalid_argument if a coefficient vector is neither empty nor of length H.
class PositionDependentInertia final : public Block {
 public:
  explicit PositionDependentInertia(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  PositionFourierSeries mass_;  ///< M(x) [kg]
  bool acceleration_input_;
};

}  // namespace mb
