#pragma once
// The paper's filters as transfer functions, shared by the blocks (q_filter, nominal_inverse, dob, f_gp,
// velocity_estimator) and the stability analysis so that both use exactly the same discretisation.
//
// Source: Jung, Yeo, Chang & Oh, "Data-driven disturbance compensation for core-type linear motors using
// TISO-GPR integrated with disturbance observers" (docs/paper.md): eq. 3 (PD), eq. 4 (P_n⁻¹), eq. 5 (Q),
// eq. 51 (Q∘P_n⁻¹), eq. 53 (F_gp), Assumption 2 (F_ẋ).

#include "models/stability/lti.h"

namespace mb {

/// Binomial low-pass ω^n/(s + ω)^n, ω = 2π·cutoff_hz [rad/s] — the Q-filter of eq. 5 (n = relative degree n_r)
/// and the F_gp filter of eq. 53. @throws std::invalid_argument unless cutoff_hz > 0 and 1 ≤ order ≤ 8.
ContinuousTf BinomialLowPass(double cutoff_hz, int order);

/// Q∘P_n⁻¹ of eq. 51: ω^n·(M_n s² + B_n s)/(s + ω)^n with P_n = 1/(M_n s² + B_n s) (eq. 4). Proper for n ≥ 2.
/// Units: N/m. @throws std::invalid_argument unless cutoff_hz > 0, 2 ≤ relative_degree ≤ 8, M_n > 0, B_n ≥ 0.
ContinuousTf QNominalInverse(double cutoff_hz, int relative_degree, double nominal_mass, double nominal_damping);

/// Rigid body P(s) = 1/(M s² + B s) from force [N] to position [m]. @throws std::invalid_argument unless M > 0,
/// B ≥ 0.
ContinuousTf RigidBodyPlant(double mass, double damping);

/// F_ẋ of Assumption 2, the velocity estimate from the sampled (quantised) position: a backward difference
/// followed by a first-order low-pass with pole a = exp(−2π·cutoff_hz·Ts):
///   F(z) = (1 − a)(1 − z⁻¹) / (Ts (1 − a z⁻¹))       [1/s],
/// unit DC slope (a ramp v·t gives v after the transient), ‖F‖₁ = 2(1 − a)/Ts. Continuous counterpart
/// ω s/(s + ω). @throws std::invalid_argument unless cutoff_hz > 0 and Ts > 0.
DiscreteTf VelocityEstimatorFilter(double cutoff_hz, double sample_time);
ContinuousTf VelocityEstimatorFilterContinuous(double cutoff_hz);

/// PD of eq. 3 with the derivative filtered by F_ẋ: C_FB(z) = K_p + K_d·F_ẋ(z) [N/m]; continuous counterpart
/// K_p + K_d ω s/(s + ω). @throws std::invalid_argument for negative gains or a bad cut-off.
DiscreteTf PdFilter(double kp, double kd, double derivative_cutoff_hz, double sample_time);
ContinuousTf PdFilterContinuous(double kp, double kd, double derivative_cutoff_hz);

}  // namespace mb
