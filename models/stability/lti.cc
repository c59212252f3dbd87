#include "models/stability/lti.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

namespace mb {

namespace {

using Complex = std::complex<double>;

// Σ c_i x^(n−i) for coefficients in descending powers.
Complex PolyvalDescending(const Eigen::VectorXd& c, Complex x) {
  Complex y = 0.0;
  for (Eigen::Index i = 0; i < c.size(); ++i) y = y * x + c(i);
  return y;
}

// Characteristic polynomial det(zI − A) = z^n + c_1 z^(n−1) + … + c_n by Faddeev–LeVerrier (exact in exact
// arithmetic, accurate for the small orders of control filters; unlike roots it needs no eigenvalue of a
// defective matrix, e.g. the repeated pole of a binomial Q-filter). Returns [1, c_1, …, c_n].
Eigen::VectorXd CharacteristicPolynomial(const Eigen::MatrixXd& A) {
  const Eigen::Index n = A.rows();
  Eigen::VectorXd c(n + 1);
  c(0) = 1.0;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index k = 1; k <= n; ++k) {
    M = A * M + c(k - 1) * I;
    c(k) = -(A * M).trace() / static_cast<double>(k);
  }
  return c;
}

void CheckContinuous(const ContinuousTf& tf) {
  if (tf.den.size() == 0 || tf.den(0) == 0.0) {
    throw std::invalid_argument("continuous transfer function: the leading denominator coefficient must be non-zero");
  }
  if (tf.num.size() == 0) throw std::invalid_argument("continuous transfer function: empty numerator");
  if (tf.num.size() > tf.den.size()) {
    throw std::invalid_argument("continuous transfer function is improper (numerator degree " +
                                std::to_string(tf.num.size() - 1) + " > denominator degree " +
                                std::to_string(tf.den.size() - 1) + "); combine it with a low-pass filter first");
  }
  if (!tf.num.allFinite() || !tf.den.allFinite()) {
    throw std::invalid_argument("continuous transfer function has non-finite coefficients");
  }
}

// A diagonal similarity x = S·z, S = diag(1, 1/ω0, …, 1/ω0^(n−1)) with ω0 = max_k |a_k|^(1/k) (a_k the monic
// denominator's coefficients): the controllable canonical form's entries, up to ω^n for a binomial filter, then all
// scale like ω0. The matrix exponential and the characteristic polynomial lose accuracy on the unbalanced form from
// relative degree 5 on (issue 11); the transfer function is unchanged by a similarity.
ContinuousSs Balanced(ContinuousSs ss) {
  const Eigen::Index n = ss.A.rows();
  double w0 = 0.0;
  for (Eigen::Index k = 1; k <= n; ++k) {
    w0 = std::max(w0, std::pow(std::abs(ss.A(0, k - 1)), 1.0 / static_cast<double>(k)));
  }
  if (!(w0 > 0.0) || !std::isfinite(w0)) return ss;
  Eigen::VectorXd scale(n);  // S's diagonal
  for (Eigen::Index i = 0; i < n; ++i) scale(i) = std::pow(w0, -static_cast<double>(i));
  ss.A = scale.cwiseInverse().asDiagonal() * ss.A * scale.asDiagonal();
  ss.B = scale.cwiseInverse().asDiagonal() * ss.B;
  ss.C = ss.C * scale.asDiagonal();
  return ss;
}

}  // namespace

Complex ContinuousTf::Evaluate(Complex s) const { return PolyvalDescending(num, s) / PolyvalDescending(den, s); }

Complex ContinuousTf::FrequencyResponse(double omega) const { return Evaluate(Complex(0.0, omega)); }

Complex DiscreteTf::FrequencyResponse(double omega) const {
  const Complex zinv = std::exp(Complex(0.0, -omega * sample_time));
  Complex nb = 0.0, na = 0.0, p = 1.0;
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    nb += b(i) * p;
    na += a(i) * p;
    p *= zinv;
  }
  return nb / na;
}

double DiscreteTf::DcGain() const { return b.sum() / a.sum(); }

double DiscreteTf::SpectralRadius() const {
  const Eigen::Index n = a.size() - 1;
  if (n == 0) return 0.0;
  // Companion matrix of z^n + a_1 z^(n−1) + … + a_n.
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  companion.row(0) = -a.tail(n).transpose();
  if (n > 1) companion.block(1, 0, n - 1, n - 1).setIdentity();
  const Eigen::VectorXcd poles = companion.eigenvalues();
  return poles.cwiseAbs().maxCoeff();
}

Discretization ParseDiscretization(const std::string& text, const std::string& where) {
  if (text == "zoh") return Discretization::kZeroOrderHold;
  if (text == "tustin") return Discretization::kTustin;
  throw std::invalid_argument(where + ": discretization '" + text + "' is unknown; use \"zoh\" or \"tustin\"");
}

const char* ToString(Discretization method) {
  return method == Discretization::kZeroOrderHold ? "zoh" : "tustin";
}

ContinuousSs Realize(const ContinuousTf& tf) {
  CheckContinuous(tf);
  const Eigen::Index n = tf.den.size() - 1;
  const Eigen::VectorXd den = tf.den / tf.den(0);
  Eigen::VectorXd num = Eigen::VectorXd::Zero(n + 1);
  num.tail(tf.num.size()) = tf.num / tf.den(0);
  ContinuousSs ss;
  ss.D = num(0);
  ss.A = Eigen::MatrixXd::Zero(n, n);
  ss.B = Eigen::VectorXd::Zero(n);
  ss.C = Eigen::RowVectorXd::Zero(n);
  if (n == 0) return ss;
  ss.A.row(0) = -den.tail(n).transpose();
  if (n > 1) ss.A.block(1, 0, n - 1, n - 1).setIdentity();
  ss.B(0) = 1.0;
  for (Eigen::Index i = 0; i < n; ++i) ss.C(i) = num(i + 1) - ss.D * den(i + 1);
  return ss;
}

DiscreteTf Discretize(const ContinuousTf& tf, double sample_time, Discretization method) {
  if (!(sample_time > 0.0) || !std::isfinite(sample_time)) {
    throw std::invalid_argument("Discretize: the sample time must be a positive number of seconds, got " +
                                std::to_string(sample_time));
  }
  const ContinuousSs ss = Balanced(Realize(tf));
  const Eigen::Index n = ss.A.rows();
  DiscreteTf out;
  out.sample_time = sample_time;
  if (n == 0) {
    out.b = Eigen::VectorXd::Constant(1, ss.D);
    out.a = Eigen::VectorXd::Ones(1);
    return out;
  }
  Eigen::MatrixXd Ad;
  Eigen::VectorXd Bd;
  Eigen::RowVectorXd Cd = ss.C;
  double Dd = ss.D;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  if (method == Discretization::kZeroOrderHold) {
    // exp([[A, B], [0, 0]]·Ts) = [[Ad, Bd], [0, 1]] (FPW eq. 4.58).
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + 1, n + 1);
    M.topLeftCorner(n, n) = ss.A * sample_time;
    M.topRightCorner(n, 1) = ss.B * sample_time;
    // Padé approximant of degree 13 with scaling and squaring (Higham, "The scaling and squaring method for the
    // matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26(4), 2005), as SciPy's expm: a truncated
    // Taylor series lost accuracy from relative degree 5 and gave an unstable filter at degree 8 (issue 11).
    const Eigen::MatrixXd E = M.exp();
    Ad = E.topLeftCorner(n, n);
    Bd = E.topRightCorner(n, 1);
  } else {
    // s = (2/Ts)(z − 1)/(z + 1): with W = (I − A·Ts/2)⁻¹, Ad = W(I + A·Ts/2), Bd = W·B·Ts, Cd = C·W,
    // Dd = D + C·W·B·Ts/2.
    const Eigen::MatrixXd W = (I - ss.A * (sample_time / 2.0)).inverse();
    Ad = W * (I + ss.A * (sample_time / 2.0));
    Bd = W * ss.B * sample_time;
    Cd = ss.C * W;
    Dd = ss.D + (ss.C * W * ss.B)(0) * sample_time / 2.0;
  }
  // Transfer function: a = det(zI − Ad) in powers of z⁻¹; b = a ⊛ h truncated to n + 1 terms, where
  // h = [Dd, Cd·Bd, Cd·Ad·Bd, …] are the Markov parameters (b(z⁻¹) = a(z⁻¹)·H(z⁻¹) is a polynomial of degree n).
  out.a = CharacteristicPolynomial(Ad);
  Eigen::VectorXd h(n + 1);
  h(0) = Dd;
  Eigen::VectorXd v = Bd;
  for (Eigen::Index k = 1; k <= n; ++k) {
    h(k) = Cd.dot(v);
    v = Ad * v;
  }
  out.b = Eigen::VectorXd::Zero(n + 1);
  for (Eigen::Index k = 0; k <= n; ++k) {
    for (Eigen::Index j = 0; j <= k; ++j) out.b(k) += out.a(j) * h(k - j);
  }
  // A ZOH equivalent of a strictly proper filter has no feedthrough; make the zero exact (not round-off).
  if (method == Discretization::kZeroOrderHold && Dd == 0.0) out.b(0) = 0.0;
  return out;
}

double FilterOutput(const DiscreteTf& tf, double u, const double* state) noexcept {
  return tf.b(0) * u + (tf.a.size() > 1 ? state[0] : 0.0);
}

void FilterUpdate(const DiscreteTf& tf, double u, double* state) noexcept {
  const Eigen::Index n = tf.a.size() - 1;
  if (n == 0) return;
  const double y = tf.b(0) * u + state[0];
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    state[i] = state[i + 1] + tf.b(i + 1) * u - tf.a(i + 1) * y;
  }
  state[n - 1] = tf.b(n) * u - tf.a(n) * y;
}

void FilterSteadyState(const DiscreteTf& tf, double u, double* state) noexcept {
  const Eigen::Index n = tf.a.size() - 1;
  if (n == 0) return;
  const double y = tf.DcGain() * u;
  double next = 0.0;
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    state[i] = next + tf.b(i + 1) * u - tf.a(i + 1) * y;
    next = state[i];
  }
}

Eigen::VectorXd ImpulseResponse(const DiscreteTf& tf, int count) {
  if (count < 0) throw std::invalid_argument("ImpulseResponse: count must be >= 0");
  Eigen::VectorXd h(count);
  Eigen::VectorXd state = Eigen::VectorXd::Zero(std::max<Eigen::Index>(tf.a.size() - 1, 1));
  for (int k = 0; k < count; ++k) {
    const double u = k == 0 ? 1.0 : 0.0;
    h(k) = FilterOutput(tf, u, state.data());
    FilterUpdate(tf, u, state.data());
  }
  return h;
}

double L1Norm(const DiscreteTf& tf, double relative_tolerance) {
  const double r = tf.SpectralRadius();
  if (!(r < 1.0)) {
    throw std::invalid_argument("L1Norm: the filter is not stable (largest pole magnitude " + std::to_string(r) +
                                " ≥ 1); its l1 norm is infinite");
  }
  // |h[k]| ≤ c·k^(n−1)·r^k: sum well past the point where r^k < tolerance, with room for the polynomial factor.
  const int n = tf.order();
  long long count = n + 1;
  if (r > 0.0) {
    const double decay = std::log(std::max(relative_tolerance, 1e-300)) / std::log(r);
    count += static_cast<long long>(std::ceil(2.0 * decay)) + 200LL * n;
  }
  count = std::min<long long>(count, 100'000'000LL);
  double sum = 0.0;
  Eigen::VectorXd state = Eigen::VectorXd::Zero(std::max(n, 1));
  for (long long k = 0; k < count; ++k) {
    const double u = k == 0 ? 1.0 : 0.0;
    sum += std::abs(FilterOutput(tf, u, state.data()));
    FilterUpdate(tf, u, state.data());
  }
  return sum;
}

double L1Norm(const Eigen::Ref<const Eigen::VectorXd>& impulse_response) { return impulse_response.cwiseAbs().sum(); }

}  // namespace mb
