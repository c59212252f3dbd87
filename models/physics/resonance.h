#pragma once
// An optional structural resonance between the motor force and the encoder: one flexible mode q added to the
// rigid-body position seen by the encoder,
//
//   x_enc = x + q,      q̈ + 2ζω_r q̇ + ω_r² q = g·F/M                                       [m]
//
// so the force-to-encoder transfer is P(s) = 1/(Ms² + Bs) + (g/M)/(s² + 2ζω_r s + ω_r²) (a collocated
// rigid-body-plus-mode model, e.g. Fig. 3 of the paper above its rigid-body band). g = 0 removes the mode.
// Source: Gawronski, "Advanced Structural Dynamics and Active Control of Structures" (2004), §2 (modal models).

namespace mb {

struct ResonanceParameters {
  double frequency_hz = 0.0;    ///< f_r [Hz] (> 0 when modal_gain ≠ 0)
  double damping_ratio = 0.05;  ///< ζ ≥ 0
  double modal_gain = 0.0;      ///< g (dimensionless participation of the mode; 0 = no resonance)
};

class StructuralResonance final {
 public:
  /// @throws std::invalid_argument if the mode is on (g ≠ 0) with f_r ≤ 0, or ζ < 0, or non-finite values.
  explicit StructuralResonance(ResonanceParameters parameters);
  bool enabled() const noexcept { return p_.modal_gain != 0.0; }
  /// q̈ for modal state (q, q̇) [m, m/s] driven by the specific force F/M [m/s²].
  double ModalAcceleration(double q, double qdot, double specific_force) const noexcept;
  const ResonanceParameters& parameters() const noexcept { return p_; }

 private:
  ResonanceParameters p_;
  double omega_ = 0.0;
};

}  // namespace mb
