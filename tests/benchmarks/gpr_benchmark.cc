// TISO-GPR benchmarks: MAP fit for N = 2,096 (the paper's D(2)) and N = 200,000 (every sample of
// a 200 s log at 1 kHz), prediction per call. The exact solver is run at N = 2,096 only: at
// N = 200,000 its N×N matrix alone is 320 GB (FitGpr refuses N > 10,000).
#include <benchmark/benchmark.h>

#include "models/gpr/exact_gp.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_recursive.h"
#include "models/gpr/sincos.h"
#include "tests/gpr/synthetic_data.h"

namespace mb {
namespace {

testing::DisturbanceSamples Samples(Eigen::Index n) {
  // Ten constant-velocity scans over the paper's 225 mm window, n/10 samples each.
  return testing::ConstantVelocityScans(0.2375, 0.4625, static_cast<int>(n / 10), 0.02, 42);
}

void BM_FitGpr(benchmark::State& state, GprSolver solver, GprKernel kernel, int restarts) {
  const auto data = Samples(state.range(0));
  GprFitOptions options;
  options.solver = solver;
  options.kernel = kernel;
  options.restarts = restarts;
  int features = 0;
  for (auto _ : state) {
    const GprModel model = FitGpr(data.x, data.xdot, data.d, options);
    features = model.feature_count();
    benchmark::DoNotOptimize(model.mean());
  }
  state.counters["N"] = static_cast<double>(data.x.size());
  state.counters["M"] = features;
  state.counters["restarts"] = restarts;
}

BENCHMARK_CAPTURE(BM_FitGpr, weight_space_PS, GprSolver::kWeightSpace, GprKernel::kPeriodicSe, 2)
    ->Arg(2096)->Arg(200000)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_FitGpr, weight_space_DS, GprSolver::kWeightSpace, GprKernel::kSeSe, 2)
    ->Arg(2096)->Arg(200000)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_FitGpr, exact_PS, GprSolver::kExact, GprKernel::kPeriodicSe, 0)
    ->Arg(2096)->Unit(benchmark::kMillisecond)->Iterations(1);

GprModel FittedModel(GprKernel kernel) {
  const auto data = Samples(2096);
  GprFitOptions options;
  options.kernel = kernel;
  return FitGpr(data.x, data.xdot, data.d, options);
}

void BM_PredictPosteriorMean(benchmark::State& state, GprKernel kernel) {
  const GprModel model = FittedModel(kernel);
  // Inputs inside the trained window (x in [0.1, 0.325] m, ẋ in [0.05, 0.5] m/s), where every feature is live:
  // outside it the SE/Hilbert part is skipped and a call would look cheaper than in the loop.
  double x = 0.1, v = 0.05;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.PredictPosteriorMean(x, v));
    x = x > 0.325 ? 0.1 : x + 1.3e-4;  // a moving stage: 0.13 m/s at 1 kHz
    v = v > 0.5 ? 0.05 : v + 1e-5;
  }
  state.counters["M"] = model.feature_count();
}
BENCHMARK_CAPTURE(BM_PredictPosteriorMean, PS, GprKernel::kPeriodicSe);
BENCHMARK_CAPTURE(BM_PredictPosteriorMean, DS, GprKernel::kSeSe);

void BM_PredictMeanAndStd(benchmark::State& state, GprKernel kernel) {
  const GprModel model = FittedModel(kernel);
  double x = 0.1, v = 0.05, mean = 0.0, std = 0.0;  // inside the trained window, as above
  for (auto _ : state) {
    model.Predict(x, v, &mean, &std);
    benchmark::DoNotOptimize(mean);
    benchmark::DoNotOptimize(std);
    x = x > 0.325 ? 0.1 : x + 1.3e-4;
    v = v > 0.5 ? 0.05 : v + 1e-5;
  }
  state.counters["M"] = model.feature_count();
}
BENCHMARK_CAPTURE(BM_PredictMeanAndStd, PS, GprKernel::kPeriodicSe);
BENCHMARK_CAPTURE(BM_PredictMeanAndStd, DS, GprKernel::kSeSe);

// The floor the prediction is measured against (docs/benchmarks.md): the arithmetic a posterior mean cannot
// avoid — one SinCosBounded per input axis and the M-long dot product ψᵀβ (Eigen's) with the features given
// (only the three entries the sines and cosines land in change per call) — and, with `with_std`, the
// quadratic form ψᵀΣψ by Eigen's symmetric matrix–vector product on the same model's covariance.
void BM_PredictFloor(benchmark::State& state, GprKernel kernel, bool with_std) {
  const GprModel model = FittedModel(kernel);
  const Eigen::VectorXd& beta = model.data().weights;
  const Eigen::MatrixXd& cov = model.data().weight_covariance;
  Eigen::VectorXd psi = Eigen::VectorXd::Constant(beta.size(), 0.1);
  Eigen::VectorXd sigma_psi(beta.size());
  double x = 0.1, v = 0.05;
  for (auto _ : state) {
    double s = 0.0, c = 0.0, sv = 0.0, cv = 0.0;
    SinCosBounded(279.25 * x, &s, &c);
    SinCosBounded(4.5 * v, &sv, &cv);
    psi(0) = s;
    psi(1) = c;
    psi(beta.size() - 1) = sv * cv;
    double mean = psi.dot(beta);
    if (with_std) {
      sigma_psi.noalias() = cov.selfadjointView<Eigen::Lower>() * psi;
      mean += psi.dot(sigma_psi);
    }
    benchmark::DoNotOptimize(mean);
    x = x > 0.325 ? 0.1 : x + 1.3e-4;
    v = v > 0.5 ? 0.05 : v + 1e-5;
  }
  state.counters["M"] = model.feature_count();
}
BENCHMARK_CAPTURE(BM_PredictFloor, mean_PS, GprKernel::kPeriodicSe, false);
BENCHMARK_CAPTURE(BM_PredictFloor, mean_DS, GprKernel::kSeSe, false);
BENCHMARK_CAPTURE(BM_PredictFloor, mean_and_std_PS, GprKernel::kPeriodicSe, true);
BENCHMARK_CAPTURE(BM_PredictFloor, mean_and_std_DS, GprKernel::kSeSe, true);

// Learning online (models/gpr/gpr_recursive.h): one rank-one posterior update per control step, O(M²), with
// exponential forgetting bounded by the prior — the budget is the 1 ms control period.
void BM_RecursiveUpdate(benchmark::State& state, GprKernel kernel) {
  GprRecursivePosterior online(FittedModel(kernel), 0.999);
  double x = 0.1, v = 0.05;
  for (auto _ : state) {
    online.Update(x, v, 0.1 * std::sin(300.0 * x));
    x = x > 0.325 ? 0.1 : x + 1.3e-4;
    v = v > 0.5 ? 0.05 : v + 1e-5;
  }
  benchmark::DoNotOptimize(online.weights().data());
  state.counters["M"] = online.model().feature_count();
}
BENCHMARK_CAPTURE(BM_RecursiveUpdate, PS, GprKernel::kPeriodicSe);
BENCHMARK_CAPTURE(BM_RecursiveUpdate, DS, GprKernel::kSeSe);

// The exact GP's prediction (eq. 22 as written, O(N)) for comparison.
void BM_ExactPosteriorMean(benchmark::State& state) {
  const GprModel model = FittedModel(GprKernel::kPeriodicSe);
  const auto data = Samples(2096);
  const Eigen::VectorXd y = data.d.array() - data.d.mean();
  const ExactGp exact(GprKernel::kPeriodicSe, model.hyperparameters(), data.x, data.xdot, y);
  double x = 0.0, v = 0.05;
  for (auto _ : state) {
    benchmark::DoNotOptimize(exact.PosteriorMean(x, v));
    x += 1.3e-4;
  }
  state.counters["N"] = static_cast<double>(data.x.size());
}
BENCHMARK(BM_ExactPosteriorMean);

}  // namespace
}  // namespace mb
