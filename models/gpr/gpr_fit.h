#pragma once
// MAP fit of the TISO-GPR (paper §3.1–3.3): centre the targets (eq. 14), maximise
// log p(y | θ) + log p(θ) over θ = log(σ²_{f,x}, ℓ_x, σ²_{f,ẋ}, ℓ_ẋ, σ²_n[, τ]) with analytic
// gradients by L-BFGS with bounds (NLopt NLOPT_LD_LBFGS) from several starts, and return the
// weight-space model at the optimum.

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "models/gpr/gpr_model.h"
#include "models/gpr/kernels.h"
#include "models/gpr/priors.h"

namespace mb {

/// Which likelihood the MAP maximises.
///  kExact:       the exact Cholesky GP (R&W Alg. 2.1), O(N³) per evaluation — the reference,
///                for N up to a few thousand.
///  kWeightSpace: Bayesian linear regression on the Fourier–Bessel / Hilbert-space features,
///                O(N·M²) once and O(M³) per evaluation — every sample of a long log.
/// Both return the same weight-space GprModel, built at the MAP hyperparameters.
enum class GprSolver { kExact, kWeightSpace };

/// "exact" or "weight_space".
std::string_view GprSolverName(GprSolver solver) noexcept;
/// Parses "exact" or "weight_space"; throws std::invalid_argument naming both.
GprSolver ParseGprSolver(std::string_view name);

/// The ceiling of GprFitOptions::restarts: each start runs up to max_evaluations (400) evaluations of the posterior.
inline constexpr int kMaxGprRestarts = 1000;
/// The range of GprFitOptions::period [m]: 1 µm to 1000 km (a pole pitch is millimetres; below 1 µm the phase
/// 2πx/τ of any position measured in metres is noise).
inline constexpr double kMinGprPeriod = 1e-6;
inline constexpr double kMaxGprPeriod = 1e6;

/// The fewest samples FitGpr fits: its MAP estimate sets up to kGprParameterCount (6) hyperparameters from the data,
/// which fewer samples than this cannot tell apart (issue 41: two rows gave a 56-feature model without a word).
inline constexpr int kMinGprSamples = 10;

struct GprFitOptions {
  GprKernel kernel = GprKernel::kPeriodicSe;
  GprSolver solver = GprSolver::kWeightSpace;
  double period = 0.0225;        ///< τ [m] (eq. 20) in [kMinGprPeriod, kMaxGprPeriod]: fixed unless estimate_period
  bool estimate_period = false;  ///< free τ under priors[kLogPeriod] ("PS" only). In weight
                                 ///< space each evaluation then re-reads the data (O(N·M²)).
  std::optional<GprPriors> priors;  ///< default: DefaultGprPriors(kernel, period, ranges, var(y))
  /// Start of the first run (default: the prior medians). With optimize = false, the model is
  /// built at exactly these hyperparameters (except the period, which is always `period`).
  std::optional<GprHyperparameters> initial;
  bool optimize = true;
  int restarts = 2;        ///< extra starts drawn from the priors (within the bounds), 0 … kMaxGprRestarts
  std::uint64_t seed = 1;  ///< of the restart draws (std::mt19937_64)
  int max_evaluations = 400;  ///< per start
  double tolerance = 1e-12;   ///< kernel truncation of the basis, relative to σ² (basis.h)
  std::string source;         ///< recorded in the provenance
  /// All samples at one velocity: false refuses them (DefaultGprPriors: "the trained velocity range … must be
  /// > 0"); true trains on the widened range of TrainedVelocityRange (FitGprToLog sets it: a table of one scan).
  bool accept_one_velocity = false;
};

/// One scan velocity: a training set whose samples all have the same ẋ = v says nothing about the velocity
/// dependence; its trained velocity range is then v ± max(10 % |v|, 1 mm/s) [m/s] (TrainedVelocityRange), so that
/// the ẋ prior (length scale ≈ range/3) and the ẋ basis are defined. The model's prediction is clamped to that range.
inline constexpr double kOneVelocityRelativeHalfWidth = 0.1;
inline constexpr double kOneVelocityMinHalfWidth = 1e-3;  // [m/s]
/// [min ẋ, max ẋ], widened as above when min = max (and the range is finite). xdot must not be empty.
GprRange TrainedVelocityRange(const Eigen::Ref<const Eigen::VectorXd>& xdot);

/// Fits the model to samples (x_i [m], ẋ_i [m/s], d_i) — d is the raw disturbance estimate;
/// the fit centres it (eq. 14) and the model adds the mean back (eq. 24).
/// Weight space: the basis is sized from `tolerance` at the current hyperparameters; after each
/// optimisation the basis is checked at the optimum and, if too small (a length scale moved),
/// rebuilt there and the optimisation resumed from the optimum (at most 4 rounds).
/// Throws std::invalid_argument for mismatched lengths, N < 2, a non-finite sample (with its
/// index), no spread in x, ẋ or d, or invalid options/priors (a period outside [kMinGprPeriod, kMaxGprPeriod], more
/// than kMaxGprRestarts restarts); std::runtime_error if every
/// start fails (the messages of the failures are included).
GprModel FitGpr(const Eigen::Ref<const Eigen::VectorXd>& x,
                const Eigen::Ref<const Eigen::VectorXd>& xdot,
                const Eigen::Ref<const Eigen::VectorXd>& y, const GprFitOptions& options);

}  // namespace mb
