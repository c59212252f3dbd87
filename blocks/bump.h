#pragma once
// bump: y = gain · b((u − c)/w), something over one stretch of the travel (a damaged spot, debris, a seal, a weak
// magnet): b(z) = 1 on the flat top |z| ≤ f, cos²(π/2 · (|z| − f)/(1 − f)) on the flanks f < |z| < 1, 0 beyond — a
// Tukey (tapered cosine) window. f = 0 is the cos² bump the diagnosis scans (position_local, models/diagnosis/
// factor_tables.cc), f → 1 a box. Its four parameters are what a refit of the stretch needs: where, how wide, how
// sharp its edges, how large. Inherited sample time; u feeds through.
// Source: F. J. Harris, "On the use of windows for harmonic analysis with the discrete Fourier transform", Proc. IEEE
// 66(1), 1978 (the Tukey window); Simulink has no such block (a 1-D Lookup Table of its shape is one).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = gain · b((u − center)/half_width; flat). Ports: in "u" (the position: m, or rad on a rotary axis), out "y"
/// (gain's unit). Parameters: center c (u's unit), half_width w > 0 (u's unit: it acts over [c − w, c + w]), flat
/// f ∈ [0, 0.99] (the flat top's share of w, default 0), gain (default 1).
/// Throws nothing: the loader (ValidateParameters, engine/parameters.h) refuses a parameter that is missing, not
/// finite or out of its bounds, naming the element, before the block is built.
class Bump final : public Block {
 public:
  explicit Bump(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  /// b(z; flat) ∈ [0, 1]; noexcept, no allocation.
  static double Shape(double z, double flat) noexcept;

 private:
  double center_, half_width_, flat_, gain_;
};

}  // namespace mb
