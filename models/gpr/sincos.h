#pragma once
// sin and cos of one bounded angle in one call, for the feature evaluation of the weight-space
// GP (models/gpr/basis.cc), where every prediction needs exactly one pair per input.
//
// glibc's sincos handles any double (Payne–Hanek reduction for huge arguments) and costs about
// 20 ns; the phases here are already reduced to [0, 2π] (periodic features) or [0, π] (Hilbert
// features), so a Cody–Waite reduction to [−π/4, π/4] by quarter turns and the fdlibm kernel
// polynomials (k_sin.c, k_cos.c; Sun Microsystems, 1993) are enough. Accuracy: within 2·eps of
// std::sin / std::cos for |θ| ≤ kSinCosMaxAngle (tests/gpr/sincos_test.cc measures it).

namespace mb {

/// Largest |θ| [rad] SinCosBounded is specified for (the reduction keeps full accuracy while
/// n·(π/2)_hi is exact, n < 2²⁰; 64 rad is far inside that and covers every caller).
inline constexpr double kSinCosMaxAngle = 64.0;

/// Writes sin θ and cos θ for |θ| ≤ kSinCosMaxAngle. No allocation, no errno, no exception;
/// larger |θ| lose accuracy gradually (no check: the callers' phases are bounded by construction).
inline void SinCosBounded(double theta, double* sin_theta, double* cos_theta) noexcept {
  // π/2 = kPio2Hi + kPio2Lo, kPio2Hi with 33 significant bits (fdlibm e_rem_pio2.c pio2_1/pio2_1t).
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2Hi = 1.57079632673412561417e+00;
  constexpr double kPio2Lo = 6.07710050650619224932e-11;
  constexpr double kRoundShift = 0x1.8p52;  // adding and subtracting it rounds to nearest
  const double n = (theta * kTwoOverPi + kRoundShift) - kRoundShift;
  const double r = (theta - n * kPio2Hi) - n * kPio2Lo;  // |r| ≤ π/4 (+ rounding)
  const double z = r * r;
  // fdlibm __kernel_sin / __kernel_cos minimax coefficients on [−π/4, π/4].
  const double s = r + r * z * (-1.66666666666666324348e-01 +
                                z * (8.33333333332248946124e-03 +
                                     z * (-1.98412698298579493134e-04 +
                                          z * (2.75573137070700676789e-06 +
                                               z * (-2.50507602534068634195e-08 +
                                                    z * 1.58969099521155010221e-10)))));
  const double c = 1.0 - 0.5 * z +
                   z * z * (4.16666666666666019037e-02 +
                            z * (-1.38888888888741095749e-03 +
                                 z * (2.48015872894767294178e-05 +
                                      z * (-2.75573143513906633035e-07 +
                                           z * (2.08757232129817482790e-09 +
                                                z * -1.13596475577881948265e-11)))));
  switch (static_cast<long>(n) & 3) {
    case 0: *sin_theta = s;  *cos_theta = c;  break;
    case 1: *sin_theta = c;  *cos_theta = -s; break;
    case 2: *sin_theta = -s; *cos_theta = -c; break;
    default: *sin_theta = -c; *cos_theta = s; break;
  }
}

}  // namespace mb
