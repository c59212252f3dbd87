#include "models/gpr/gpr_fit.h"

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "models/gpr/basis.h"
#include "models/gpr/exact_gp.h"
#include "models/gpr/weight_space.h"

#ifndef MB_VERSION
#define MB_VERSION "unknown"
#endif

namespace mb {
namespace {

// Above this the exact solver's N×N matrices (8·N² bytes, several of them) do not fit.
constexpr Eigen::Index kMaxExactSamples = 10000;
constexpr int kMaxBasisRounds = 4;
// The basis is built with this much headroom below the tolerance so that small moves of the
// length scales during the optimisation stay within it.
constexpr double kBasisHeadroom = 1e-2;

using FreeMask = std::array<bool, kGprParameterCount>;
// Log posterior (to maximise) at θ; adds its full-length gradient to *gradient if given.
using LogPosterior = std::function<double(const Eigen::VectorXd&, Eigen::VectorXd*)>;

struct MapResult {
  Eigen::VectorXd theta;
  double log_posterior = -std::numeric_limits<double>::infinity();
  std::vector<std::string> failures;
};

// State of one L-BFGS run, reached from NLopt's C-style callback.
struct Run {
  const LogPosterior* log_posterior = nullptr;
  const std::vector<int>* index = nullptr;
  Eigen::VectorXd theta;  // full θ; the free entries are overwritten at each evaluation
  Eigen::VectorXd best_theta;
  double best = -std::numeric_limits<double>::infinity();
  std::string failure;
};

double NegativeLogPosterior(const std::vector<double>& z, std::vector<double>& grad, void* data) {
  Run& run = *static_cast<Run*>(data);
  const std::vector<int>& index = *run.index;
  for (std::size_t k = 0; k < index.size(); ++k) run.theta(index[k]) = z[k];
  try {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(kGprParameterCount);
    const double value = (*run.log_posterior)(run.theta, grad.empty() ? nullptr : &g);
    if (!std::isfinite(value) || !g.allFinite()) {
      throw std::runtime_error("the log posterior or its gradient is not finite");
    }
    for (std::size_t k = 0; k < grad.size(); ++k) grad[k] = -g(index[k]);
    if (value > run.best) {
      run.best = value;
      run.best_theta = run.theta;
    }
    return -value;
  } catch (const std::exception& e) {
    run.failure = e.what();
    throw nlopt::forced_stop();
  }
}

std::string ThetaText(const Eigen::VectorXd& theta) {
  std::string text;
  for (int i = 0; i < kGprParameterCount; ++i) {
    text += (i ? ", " : "") + std::string(GprParameterName(i)) + " = " +
            std::to_string(std::exp(theta(i)));
  }
  return text;
}

// L-BFGS with bounds (NLopt LD_LBFGS) on the free log-parameters from each start; keeps the best
// point any evaluation reached, so NLopt's round-off stops lose nothing.
MapResult MaximizeLogPosterior(const LogPosterior& log_posterior,
                               const std::vector<Eigen::VectorXd>& starts, const FreeMask& free,
                               const GprPriors& priors, int max_evaluations) {
  std::vector<int> index;
  for (int i = 0; i < kGprParameterCount; ++i) {
    if (free[static_cast<std::size_t>(i)]) index.push_back(i);
  }
  const auto dim = static_cast<unsigned>(index.size());
  std::vector<double> lower(dim);
  std::vector<double> upper(dim);
  for (unsigned k = 0; k < dim; ++k) {
    const auto& prior = priors[static_cast<std::size_t>(index[k])];
    lower[k] = std::log(prior.lower);
    upper[k] = std::log(prior.upper);
  }
  MapResult result;
  for (const Eigen::VectorXd& start : starts) {
    Run run;
    run.log_posterior = &log_posterior;
    run.index = &index;
    run.theta = start;
    std::vector<double> z(dim);
    for (unsigned k = 0; k < dim; ++k) z[k] = std::clamp(start(index[k]), lower[k], upper[k]);
    nlopt::opt opt(nlopt::LD_LBFGS, dim);
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_min_objective(NegativeLogPosterior, &run);
    opt.set_ftol_rel(1e-12);
    opt.set_xtol_rel(1e-9);
    opt.set_maxeval(max_evaluations);
    double minimum = 0.0;
    try {
      opt.optimize(z, minimum);
    } catch (const nlopt::roundoff_limited&) {
      // The best point reached is kept below; round-off near the optimum is expected.
    } catch (const nlopt::forced_stop&) {
      result.failures.push_back("start at " + ThetaText(start) + ": " + run.failure);
      continue;
    } catch (const std::exception& e) {
      if (!std::isfinite(run.best)) {
        result.failures.push_back("start at " + ThetaText(start) + ": NLopt: " + e.what());
        continue;
      }
    }
    if (run.best > result.log_posterior) {
      result.log_posterior = run.best;
      result.theta = run.best_theta;
    }
  }
  return result;
}

std::string NowUtc() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

void ValidateInputs(const Eigen::Ref<const Eigen::VectorXd>& x,
                    const Eigen::Ref<const Eigen::VectorXd>& xdot,
                    const Eigen::Ref<const Eigen::VectorXd>& y, const GprFitOptions& options) {
  if (x.size() != xdot.size() || x.size() != y.size()) {
    throw std::invalid_argument("FitGpr: x, xdot and y must have the same length (got " +
                                std::to_string(x.size()) + ", " + std::to_string(xdot.size()) +
                                ", " + std::to_string(y.size()) + ")");
  }
  if (x.size() < kMinGprSamples) {
    throw std::invalid_argument(fmt::format(
        "{}{} training sample{}, too few for a GP fit: it needs at least {} (its hyperparameters are estimated "
        "from the data); give a longer record{}",
        options.source.empty() ? "" : options.source + ": ", x.size(), x.size() == 1 ? "" : "s", kMinGprSamples,
        options.source.empty() ? "" : " or a wider --window"));
  }
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x(i)) || !std::isfinite(xdot(i)) || !std::isfinite(y(i))) {
      throw std::invalid_argument("FitGpr: sample " + std::to_string(i) + " is not finite (x = " +
                                  std::to_string(x(i)) + ", xdot = " + std::to_string(xdot(i)) +
                                  ", y = " + std::to_string(y(i)) + "): remove it from the data");
    }
  }
  if (!(options.period >= kMinGprPeriod && options.period <= kMaxGprPeriod)) {  // NaN fails too
    throw std::invalid_argument(fmt::format(
        "the period {:g} m is outside the valid range [{:g}, {:g}] m; give the spatial period of the disturbance in "
        "metres (e.g. the pole pitch, 0.0225 for 22.5 mm: fit-gpr --period)",
        options.period, kMinGprPeriod, kMaxGprPeriod));
  }
  if (options.restarts < 0 || options.restarts > kMaxGprRestarts) {
    throw std::invalid_argument(fmt::format(
        "{} restarts is outside the valid range [0, {}] (each start runs up to {} evaluations of the posterior); "
        "give fewer (fit-gpr --restarts; 2 to 10 is usual)",
        options.restarts, kMaxGprRestarts, options.max_evaluations));
  }
  if (options.max_evaluations < 1) {
    throw std::invalid_argument("FitGpr: max_evaluations must be >= 1");
  }
  if (!(options.tolerance > 0.0 && options.tolerance < 1.0)) {
    throw std::invalid_argument("FitGpr: tolerance must lie in (0, 1), got " +
                                std::to_string(options.tolerance));
  }
  if (options.estimate_period && options.kernel != GprKernel::kPeriodicSe) {
    throw std::invalid_argument("FitGpr: estimate_period needs the \"PS\" kernel (\"DS\" has no period)");
  }
  if (options.solver == GprSolver::kExact && x.size() > kMaxExactSamples) {
    throw std::invalid_argument("FitGpr: the exact solver needs O(N²) memory and O(N³) time; N = " +
                                std::to_string(x.size()) + " exceeds its limit of " +
                                std::to_string(kMaxExactSamples) +
                                ": use the weight_space solver (same model, O(N·M²))");
  }
}

// Start points: θ0, then `restarts` draws from the priors of the free parameters (clamped).
std::vector<Eigen::VectorXd> Starts(const Eigen::VectorXd& theta0, const GprPriors& priors,
                                    const FreeMask& free, int restarts, std::uint64_t seed) {
  std::vector<Eigen::VectorXd> starts{theta0};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int r = 0; r < restarts; ++r) {
    Eigen::VectorXd theta = theta0;
    for (int i = 0; i < kGprParameterCount; ++i) {
      if (!free[static_cast<std::size_t>(i)]) continue;
      const auto& p = priors[static_cast<std::size_t>(i)];
      const double lo = std::log(p.lower);
      const double hi = std::log(p.upper);
      const double draw = std::isfinite(p.log_sd)
                              ? std::log(p.median) + p.log_sd * normal(rng)
                              : (std::isfinite(hi) ? lo + (hi - lo) * uniform(rng)
                                                   : lo + 3.0 * std::abs(normal(rng)));
      theta(i) = std::clamp(draw, lo, hi);
    }
    starts.push_back(theta);
  }
  return starts;
}

std::string FailureText(const std::vector<std::string>& failures) {
  std::string text;
  for (const auto& f : failures) text += "\n  " + f;
  return text;
}

}  // namespace

std::string_view GprSolverName(GprSolver solver) noexcept {
  return solver == GprSolver::kExact ? "exact" : "weight_space";
}

GprSolver ParseGprSolver(std::string_view name) {
  if (name == "exact") return GprSolver::kExact;
  if (name == "weight_space") return GprSolver::kWeightSpace;
  throw std::invalid_argument("unknown GPR solver \"" + std::string(name) +
                              "\": use \"weight_space\" (default) or \"exact\"");
}

GprRange TrainedVelocityRange(const Eigen::Ref<const Eigen::VectorXd>& xdot) {
  const GprRange range{xdot.minCoeff(), xdot.maxCoeff()};
  if (range.max > range.min || !std::isfinite(range.min)) return range;
  const double v = range.min;  // one scan velocity: widened so that the velocity prior and basis are defined
  const double half_width = std::max(kOneVelocityRelativeHalfWidth * std::abs(v), kOneVelocityMinHalfWidth);
  return {v - half_width, v + half_width};
}

namespace {

// The MAP problem FitGpr solves: the centred targets, the priors, which parameters are free, the trained ranges.
struct MapProblem {
  Eigen::Ref<const Eigen::VectorXd> x, xdot;
  const Eigen::VectorXd& yc;
  const GprFitOptions& options;
  const GprPriors& priors;
  FreeMask free;
  GprRange x_range, xdot_range;

  // exp(log τ) need not return τ to the last bit: a fixed period must stay exactly the basis' period.
  GprHyperparameters Hyperparameters(const Eigen::VectorXd& th) const {
    GprHyperparameters hp = FromLogParameters(th);
    if (!options.estimate_period) hp.period = options.period;
    return hp;
  }
  double LogPrior(const Eigen::VectorXd& th, Eigen::VectorXd* g) const { return GprLogPrior(priors, th, free, g); }
};

// The maximum a posteriori: log hyperparameters, the log posterior there, and the basis for them.
struct MapFit {
  Eigen::VectorXd theta;
  double log_posterior = 0.0;
  GprBasis basis;
};

// The starting hyperparameters: options.initial, else the priors' medians; the period is options.period.
GprHyperparameters InitialHyperparameters(const GprFitOptions& options, const GprPriors& priors) {
  GprHyperparameters hp0;
  if (options.initial) {
    hp0 = *options.initial;
  } else {
    hp0.signal_variance_x = priors[kLogSignalVarianceX].median;
    hp0.length_scale_x = priors[kLogLengthScaleX].median;
    hp0.signal_variance_xdot = priors[kLogSignalVarianceXdot].median;
    hp0.length_scale_xdot = priors[kLogLengthScaleXdot].median;
    hp0.noise_variance = priors[kLogNoiseVariance].median;
  }
  hp0.period = options.period;
  return hp0;
}

// MAP with the exact (O(N³)) log marginal likelihood, then the basis for the result.
MapFit FitExact(const MapProblem& p, const Eigen::VectorXd& theta0) {
  const GprFitOptions& options = p.options;
  const LogPosterior objective = [&](const Eigen::VectorXd& th, Eigen::VectorXd* g) {
    const double lml = ExactLogMarginalLikelihood(options.kernel, p.Hyperparameters(th), p.x, p.xdot, p.yc, g);
    return lml + p.LogPrior(th, g);
  };
  const MapResult map = MaximizeLogPosterior(
      objective, Starts(theta0, p.priors, p.free, options.restarts, options.seed), p.free, p.priors,
      options.max_evaluations);
  if (!std::isfinite(map.log_posterior)) {
    throw std::runtime_error("FitGpr (exact): every start failed:" + FailureText(map.failures));
  }
  return {map.theta, map.log_posterior,
          ChooseGprBasis(options.kernel, p.Hyperparameters(map.theta), p.x_range, p.xdot_range, options.tolerance)};
}

// MAP in weight space: the basis chosen with headroom for the start, refit until it suffices for the hyperparameters
// found (at most kMaxBasisRounds), then tightened to the tolerance if it still does not.
MapFit FitWeightSpace(const MapProblem& p, const GprHyperparameters& hp0, Eigen::VectorXd theta) {
  const GprFitOptions& options = p.options;
  GprBasis basis =
      ChooseGprBasis(options.kernel, hp0, p.x_range, p.xdot_range, options.tolerance * kBasisHeadroom);
  double log_posterior = 0.0;
  GprFeatureStatistics stats;
  for (int round = 0; round < kMaxBasisRounds; ++round) {
    stats = AccumulateGprFeatureStatistics(basis, p.x, p.xdot, p.yc, options.estimate_period);
    const LogPosterior objective = [&](const Eigen::VectorXd& th, Eigen::VectorXd* g) {
      const GprHyperparameters hp = p.Hyperparameters(th);
      if (options.estimate_period && hp.period != stats.basis.period) {
        GprBasis moved = stats.basis;
        moved.period = hp.period;
        stats = AccumulateGprFeatureStatistics(moved, p.x, p.xdot, p.yc, true);
      }
      return WeightSpaceLogMarginalLikelihood(stats, hp, g) + p.LogPrior(th, g);
    };
    const std::vector<Eigen::VectorXd> starts = round == 0
                                                    ? Starts(theta, p.priors, p.free, options.restarts, options.seed)
                                                    : std::vector<Eigen::VectorXd>{theta};
    const MapResult map = MaximizeLogPosterior(objective, starts, p.free, p.priors, options.max_evaluations);
    if (!std::isfinite(map.log_posterior)) {
      throw std::runtime_error("FitGpr (weight_space): every start failed:" + FailureText(map.failures));
    }
    theta = map.theta;
    log_posterior = map.log_posterior;
    const GprHyperparameters hp = p.Hyperparameters(theta);
    basis.period = hp.period;
    if (GprBasisSuffices(basis, hp, p.x_range, p.xdot_range, options.tolerance)) break;
    basis = ChooseGprBasis(options.kernel, hp, p.x_range, p.xdot_range, options.tolerance * kBasisHeadroom);
  }
  const GprHyperparameters hp = p.Hyperparameters(theta);
  if (!GprBasisSuffices(basis, hp, p.x_range, p.xdot_range, options.tolerance)) {
    basis = ChooseGprBasis(options.kernel, hp, p.x_range, p.xdot_range, options.tolerance);
  }
  return {theta, log_posterior, basis};
}

}  // namespace

GprModel FitGpr(const Eigen::Ref<const Eigen::VectorXd>& x,
                const Eigen::Ref<const Eigen::VectorXd>& xdot,
                const Eigen::Ref<const Eigen::VectorXd>& y, const GprFitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  ValidateInputs(x, xdot, y, options);
  const double mean = y.mean();
  const Eigen::VectorXd yc = y.array() - mean;  // eq. 14
  const double variance = yc.squaredNorm() / static_cast<double>(yc.size());
  const GprRange x_range{x.minCoeff(), x.maxCoeff()};
  const GprRange xdot_range =
      options.accept_one_velocity ? TrainedVelocityRange(xdot) : GprRange{xdot.minCoeff(), xdot.maxCoeff()};
  if (!(variance > 0.0)) {
    throw std::invalid_argument("FitGpr: the targets y are constant: nothing to regress");
  }
  const GprPriors priors = options.priors.value_or(
      DefaultGprPriors(options.kernel, options.period, x_range, xdot_range, variance));
  ValidateGprPriors(priors);

  FreeMask free{};
  free.fill(true);
  free[kLogPeriod] = options.estimate_period;
  const GprHyperparameters hp0 = InitialHyperparameters(options, priors);
  const Eigen::VectorXd theta0 = ToLogParameters(hp0);
  if (!theta0.allFinite()) {
    throw std::invalid_argument("FitGpr: the initial hyperparameters must all be finite and > 0");
  }
  const MapProblem problem{x, xdot, yc, options, priors, free, x_range, xdot_range};
  const MapFit fit = !options.optimize ? MapFit{theta0, 0.0, ChooseGprBasis(options.kernel, hp0, x_range, xdot_range,
                                                                            options.tolerance)}
                     : options.solver == GprSolver::kExact ? FitExact(problem, theta0)
                                                           : FitWeightSpace(problem, hp0, theta0);

  GprModelData data;
  data.kernel = options.kernel;
  data.hyperparameters = problem.Hyperparameters(fit.theta);
  data.basis = fit.basis;
  data.mean = mean;
  data.x_range = x_range;
  data.xdot_range = xdot_range;
  const GprFeatureStatistics stats =
      AccumulateGprFeatureStatistics(fit.basis, x, xdot, yc, /*period_derivative=*/false);
  GprWeightPosterior posterior = SolveGprWeightPosterior(stats, data.hyperparameters);
  data.weights = std::move(posterior.weights);
  data.weight_covariance = std::move(posterior.covariance);

  GprProvenance& prov = data.provenance;
  prov.created_utc = NowUtc();
  prov.library_version = MB_VERSION;
  prov.solver = std::string(GprSolverName(options.solver));
  prov.source = options.source;
  prov.sample_count = static_cast<std::int64_t>(x.size());
  prov.log_marginal_likelihood = posterior.log_marginal_likelihood;
  prov.log_posterior = options.optimize ? fit.log_posterior
                                        : posterior.log_marginal_likelihood + problem.LogPrior(fit.theta, nullptr);
  prov.tolerance = options.tolerance;
  prov.period_estimated = options.estimate_period && options.optimize;
  prov.priors = priors;
  prov.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return GprModel(std::move(data));
}

}  // namespace mb
