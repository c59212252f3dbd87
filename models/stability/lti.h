#pragma once
// Linear time-invariant SISO filters: continuous transfer functions, their discretisation (zero-order hold and
// Tustin), an allocation-free direct-form-II-transposed runtime for blocks, frequency and impulse responses and
// the l1 norm (the gain ‖·‖₁ of the paper's small-gain analysis, section 4.2).
//
// Sources: Franklin, Powell & Workman, "Digital Control of Dynamic Systems" (3rd ed.), §4.3 (ZOH equivalent,
// eq. 4.58), §6.3.2 (bilinear/Tustin), §4.2 (controllable canonical form); Desoer & Vidyasagar, "Feedback
// Systems: Input-Output Properties" (l1 norm of a stable discrete system = its ℓ∞-induced gain).

#include <complex>
#include <string>

#include <Eigen/Core>

namespace mb {

/// H(s) = (n_0 s^m + … + n_m)/(d_0 s^n + … + d_n), coefficients in descending powers of s, m ≤ n (proper).
struct ContinuousTf {
  Eigen::VectorXd num;  ///< numerator, descending powers of s
  Eigen::VectorXd den;  ///< denominator, descending powers of s, den(0) ≠ 0

  /// H(jω) for ω in rad/s.
  std::complex<double> FrequencyResponse(double omega) const;
  /// H(s) at a complex s.
  std::complex<double> Evaluate(std::complex<double> s) const;
  int order() const { return static_cast<int>(den.size()) - 1; }
};

/// H(z) = (b_0 + b_1 z⁻¹ + … + b_n z⁻ⁿ)/(1 + a_1 z⁻¹ + … + a_n z⁻ⁿ) at sample time Ts [s].
/// `b` and `a` have the same length n + 1, a(0) = 1. Strictly proper (no direct feedthrough) iff b(0) = 0.
struct DiscreteTf {
  Eigen::VectorXd b;         ///< numerator in powers of z⁻¹ (length n + 1)
  Eigen::VectorXd a;         ///< denominator in powers of z⁻¹ (length n + 1), a(0) = 1
  double sample_time = 0.0;  ///< Ts [s]

  int order() const { return static_cast<int>(a.size()) - 1; }
  bool strictly_proper() const { return b(0) == 0.0; }
  /// H(e^{jωTs}) for ω in rad/s.
  std::complex<double> FrequencyResponse(double omega) const;
  /// H(1): the gain for a constant input.
  double DcGain() const;
  /// Largest pole magnitude (< 1 for a stable filter).
  double SpectralRadius() const;
};

/// How a continuous filter becomes a discrete one.
enum class Discretization {
  kZeroOrderHold,  ///< exact for an input held constant over each period (FPW eq. 4.58); strictly proper if H is
  kTustin,         ///< bilinear s = (2/Ts)(z − 1)/(z + 1); keeps stability and the DC gain, biproper
};

/// "zoh" or "tustin" → Discretization. @throws std::invalid_argument naming `where` and the accepted values.
Discretization ParseDiscretization(const std::string& text, const std::string& where);
const char* ToString(Discretization method);

/// Discretises a proper continuous filter at sample time `sample_time` [s] (through its controllable canonical
/// state space; the matrix exponential for ZOH). @throws std::invalid_argument if H is improper, den(0) = 0 or
/// sample_time ≤ 0.
DiscreteTf Discretize(const ContinuousTf& tf, double sample_time, Discretization method);

/// Continuous state space ẋ = A x + B u, y = C x + D u (controllable canonical form of a proper H(s)).
struct ContinuousSs {
  Eigen::MatrixXd A;  ///< n×n
  Eigen::VectorXd B;  ///< n
  Eigen::RowVectorXd C;  ///< 1×n
  double D = 0.0;
};
/// Controllable canonical realisation (FPW §4.2). @throws std::invalid_argument if H is improper or den(0) = 0.
ContinuousSs Realize(const ContinuousTf& tf);

/// Output of a direct-form-II-transposed filter for input u with state `state` (length order()); reads the
/// state only. noexcept and allocation-free (the block real-time path). y = b_0 u + s_1.
double FilterOutput(const DiscreteTf& tf, double u, const double* state) noexcept;
/// Advances the state by one sample for input u (recomputes y internally). noexcept, allocation-free.
void FilterUpdate(const DiscreteTf& tf, double u, double* state) noexcept;
/// State that makes the filter sit at rest with constant input u and output DcGain()·u (for a filter whose
/// DC gain is finite); writes order() values.
void FilterSteadyState(const DiscreteTf& tf, double u, double* state) noexcept;

/// The first `count` samples of the impulse response h[k] (h[0] = b_0).
Eigen::VectorXd ImpulseResponse(const DiscreteTf& tf, int count);

/// ‖H‖₁ = Σ_k |h[k]| (the ℓ∞→ℓ∞ induced gain of a stable discrete system). Sums until the remaining tail is
/// below `relative_tolerance`·sum (bounded through the spectral radius). @throws std::invalid_argument if the
/// filter is not strictly stable (spectral radius ≥ 1), naming the radius.
double L1Norm(const DiscreteTf& tf, double relative_tolerance = 1e-10);

/// ‖h‖₁ of a sampled impulse response (sum of |h[k]|).
double L1Norm(const Eigen::Ref<const Eigen::VectorXd>& impulse_response);

}  // namespace mb
