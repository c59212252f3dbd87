#include "models/diagnosis/signal_processing.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "models/diagnosis/fft.h"
#include "models/diagnosis/frequency_response.h"

namespace mb {
namespace {

using ::testing::HasSubstr;
constexpr double kPi = std::numbers::pi;

Eigen::VectorXd Time(Eigen::Index n, double ts) { return Eigen::VectorXd::LinSpaced(n, 0.0, static_cast<double>(n - 1) * ts); }

// The longest length ≤ n with prime factors 2, 3 and 5 only, against a search by trial division.
TEST(FastFftLength, IsTheLongestLengthOfTwosThreesAndFivesUpToN) {
  const auto smooth = [](std::ptrdiff_t m) {
    for (std::ptrdiff_t p : {2, 3, 5}) {
      while (m % p == 0) m /= p;
    }
    return m == 1;
  };
  for (std::ptrdiff_t n = 1; n <= 5000; ++n) {
    std::ptrdiff_t expected = n;
    while (!smooth(expected)) --expected;
    ASSERT_EQ(FastFftLength(n), expected) << "n = " << n;
  }
  EXPECT_EQ(FastFftLength(4166), 4096);  // a sixth of 25 000 samples: 2 · 2083 is no fast length
  EXPECT_EQ(FastFftLength(0), 1);
}

// Forward against the DFT's sum on a length with a prime factor (7) and on a fast one, the half spectrum, and the real
// inverse of a full spectrum.
TEST(Fft, IsTheDiscreteFourierTransformAndItsInverse) {
  for (std::size_t n : {14u, 16u}) {
    std::vector<double> x(n);
    for (std::size_t j = 0; j < n; ++j) x[j] = std::sin(0.7 * static_cast<double>(j * j)) + 0.1 * static_cast<double>(j);
    std::vector<std::complex<double>> full, half;
    Fft().Forward(x, &full);
    Fft(/*half_spectrum=*/true).Forward(x, &half);
    ASSERT_EQ(full.size(), n);
    ASSERT_EQ(half.size(), n / 2 + 1);
    for (std::size_t k = 0; k < n; ++k) {
      std::complex<double> sum = 0.0;
      for (std::size_t j = 0; j < n; ++j) {
        sum += x[j] * std::polar(1.0, -2.0 * kPi * static_cast<double>(j * k) / static_cast<double>(n));
      }
      EXPECT_NEAR(std::abs(full[k] - sum), 0.0, 1e-12) << "n = " << n << ", k = " << k;
      if (k <= n / 2) {
        EXPECT_NEAR(std::abs(half[k] - sum), 0.0, 1e-12) << "n = " << n << ", k = " << k;
      }
    }
    std::vector<double> back;
    Fft().Inverse(full, &back);
    ASSERT_EQ(back.size(), n);
    for (std::size_t j = 0; j < n; ++j) EXPECT_NEAR(back[j], x[j], 1e-13) << "n = " << n << ", j = " << j;
  }
}

TEST(ZeroPhaseLowPass, PassesRampAndHasNoPhaseLag) {
  const double ts = 1e-3;
  const Eigen::VectorXd t = Time(4000, ts);
  const Eigen::VectorXd ramp = 0.3 * t.array() + 0.1;
  EXPECT_LT((ZeroPhaseLowPass(ramp, ts, 20.0) - ramp).cwiseAbs().maxCoeff(), 1e-8);  // IIR round-off
  // A 2 Hz sine through a 20 Hz forward-backward Butterworth: gain |H|² = 1/(1 + (2/20)^4), zero phase.
  const Eigen::VectorXd s = (2.0 * kPi * 2.0 * t.array()).sin();
  const Eigen::VectorXd f = ZeroPhaseLowPass(s, ts, 20.0);
  const double gain = 1.0 / (1.0 + std::pow(std::tan(kPi * 2.0 * ts) / std::tan(kPi * 20.0 * ts), 4));
  const Eigen::VectorXd mid = f.segment(1000, 2000) - gain * s.segment(1000, 2000);
  EXPECT_LT(mid.cwiseAbs().maxCoeff(), 1e-6);
  // At the cut-off the forward-backward gain is 1/2 (−6 dB).
  const Eigen::VectorXd sc = (2.0 * kPi * 20.0 * t.array()).sin();
  const Eigen::VectorXd fc = ZeroPhaseLowPass(sc, ts, 20.0);
  EXPECT_NEAR(fc.segment(1000, 2000).cwiseAbs().maxCoeff(), 0.5, 5e-3);
}

// filtfilt as written out in the textbook way (Gustafsson 1996): the padded signal run through the section, reversed,
// run again, reversed back. The reference for the interleaved forward-backward runs below.
Eigen::VectorXd TextbookFiltFilt(const Eigen::VectorXd& signal, double ts, double cutoff_hz) {
  const Eigen::Index n = signal.size();
  const double k = std::tan(kPi * cutoff_hz * ts), r2 = std::numbers::sqrt2, norm = 1.0 / (1.0 + r2 * k + k * k);
  const double b0 = k * k * norm, b1 = 2.0 * k * k * norm, b2 = k * k * norm, a1 = 2.0 * (k * k - 1.0) * norm,
               a2 = (1.0 - r2 * k + k * k) * norm;
  const Eigen::Index pad =
      std::min<Eigen::Index>(n - 1, std::max<Eigen::Index>(9, static_cast<Eigen::Index>(std::ceil(3.0 / (cutoff_hz * ts)))));
  std::vector<double> x;
  for (Eigen::Index i = 0; i < pad; ++i) x.push_back(2.0 * signal(0) - signal(pad - i));
  for (Eigen::Index i = 0; i < n; ++i) x.push_back(signal(i));
  for (Eigen::Index i = 0; i < pad; ++i) x.push_back(2.0 * signal(n - 1) - signal(n - 2 - i));
  const auto run = [&] {
    double z2 = (b2 - a2) * x.front(), z1 = (b1 - a1) * x.front() + z2;
    for (double& v : x) {
      const double in = v, out = b0 * in + z1;
      z1 = b1 * in - a1 * out + z2;
      z2 = b2 * in - a2 * out;
      v = out;
    }
  };
  run();
  std::reverse(x.begin(), x.end());
  run();
  std::reverse(x.begin(), x.end());
  return Eigen::Map<const Eigen::VectorXd>(x.data() + pad, n);
}

// Seven columns (a group of four and one of three) of different signals, filtered together, are each column filtered
// alone, and that is the textbook filtfilt, to the last bit: the interleaving changes no operation.
TEST(ZeroPhaseLowPass, ColumnsTogetherAreEachColumnAloneBitForBit) {
  const double ts = 1e-3;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  Eigen::MatrixXd columns(1500, 7);
  for (Eigen::Index j = 0; j < columns.cols(); ++j) {
    for (Eigen::Index i = 0; i < columns.rows(); ++i) {
      columns(i, j) = std::sin(0.01 * static_cast<double>((j + 1) * i)) + 0.1 * noise(rng) + static_cast<double>(j);
    }
  }
  Eigen::MatrixXd together = columns;
  ZeroPhaseLowPassColumns(together, ts, 30.0);
  for (Eigen::Index j = 0; j < columns.cols(); ++j) {
    const Eigen::VectorXd alone = ZeroPhaseLowPass(columns.col(j), ts, 30.0);
    const Eigen::VectorXd textbook = TextbookFiltFilt(columns.col(j), ts, 30.0);
    EXPECT_EQ((together.col(j) - alone).cwiseAbs().maxCoeff(), 0.0) << "column " << j;
    EXPECT_EQ((alone - textbook).cwiseAbs().maxCoeff(), 0.0) << "column " << j;
    EXPECT_GT((alone - columns.col(j)).cwiseAbs().maxCoeff(), 0.01) << "the filter acts";
  }
  Eigen::MatrixXd too_short = Eigen::MatrixXd::Ones(2, 3);
  EXPECT_THROW(ZeroPhaseLowPassColumns(too_short, ts, 30.0), std::invalid_argument);
  EXPECT_EQ(too_short, Eigen::MatrixXd::Ones(2, 3)) << "nothing changed before the throw";
}

TEST(ZeroPhaseLowPass, RejectsCutoffAboveNyquist) {
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(10);
  try {
    ZeroPhaseLowPass(x, 1e-3, 600.0);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("must lie in (0, 500 Hz)"));
  }
}

TEST(CentralDifference, ExactForQuadraticsOnNonUniformGrid) {
  Eigen::VectorXd t(6);
  t << 0.0, 0.1, 0.25, 0.3, 0.5, 0.8;
  const Eigen::VectorXd y = 2.0 * t.array().square() - t.array() + 3.0;
  const Eigen::VectorXd d = CentralDifference(t, y);
  const Eigen::VectorXd expected = 4.0 * t.array() - 1.0;
  EXPECT_LT((d - expected).cwiseAbs().maxCoeff(), 1e-12);
}

// A force held over each sample period drives a mass exactly (closed form between samples): the second difference of
// the sampled position is h²/m times the mean of the two forces around each instant, i.e. the held force as
// HeldSignalAtSampleInstants gives it, not the raw sample (which leads by half a period).
TEST(HeldSignalAtSampleInstants, IsWhatTheSecondDifferenceOfTheMotionSees) {
  const double h = 1e-3, m = 2.0;
  const Eigen::Index n = 400;
  Eigen::VectorXd u(n), x(n);
  double position = 0.0, velocity = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    u(k) = std::sin(2.0 * kPi * 17.0 * static_cast<double>(k) * h) + (k % 7 == 0 ? 0.5 : 0.0);
    x(k) = position;
    position += h * velocity + 0.5 * h * h * u(k) / m;  // u(k) held over [t_k, t_k+1)
    velocity += h * u(k) / m;
  }
  const Eigen::VectorXd held = HeldSignalAtSampleInstants(u, {0});
  double worst_held = 0.0, worst_raw = 0.0;
  for (Eigen::Index k = 1; k + 1 < n; ++k) {
    const double seen = m * (x(k + 1) - 2.0 * x(k) + x(k - 1)) / (h * h);
    worst_held = std::max(worst_held, std::abs(seen - held(k)));
    worst_raw = std::max(worst_raw, std::abs(seen - u(k)));
  }
  EXPECT_LT(worst_held, 1e-6);
  EXPECT_GT(worst_raw, 0.1);
  EXPECT_EQ(held(0), u(0));
  // Per segment: the first sample of each is kept, nothing is averaged across a gap.
  const Eigen::VectorXd split = HeldSignalAtSampleInstants(u, {0, 100});
  EXPECT_EQ(split(100), u(100));
  EXPECT_EQ(split(101), 0.5 * (u(100) + u(101)));
}

TEST(DeriveMotion, RecoversVelocityAndAccelerationOfSmoothMotion) {
  const double ts = 1e-3;
  const Eigen::VectorXd t = Time(5000, ts);
  const Eigen::VectorXd x = 0.1 * (2.0 * kPi * 0.5 * t.array()).sin();
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 1e-7);
  Eigen::VectorXd xm = x;
  for (auto& v : xm) v += noise(rng);
  const MotionDerivatives m = DeriveMotion(t, xm, 30.0);
  const Eigen::VectorXd v = 0.1 * kPi * (2.0 * kPi * 0.5 * t.array()).cos();
  const Eigen::VectorXd a = -0.1 * kPi * kPi * (2.0 * kPi * 0.5 * t.array()).sin();
  EXPECT_LT((m.velocity - v).segment(100, 4800).cwiseAbs().maxCoeff(), 2e-3 * 0.1 * kPi);
  EXPECT_LT((m.acceleration - a).segment(100, 4800).cwiseAbs().maxCoeff(), 2e-2 * 0.1 * kPi * kPi);
}

TEST(FitMetrics, RmseAndFitPercentFollowMatlabDefinitions) {
  Eigen::VectorXd y(4), yh(4);
  y << 1, 2, 3, 4;
  yh << 1, 2, 3, 5;
  EXPECT_DOUBLE_EQ(Rmse(y, yh), 0.5);
  // ‖y − ŷ‖ = 1, ‖y − ȳ‖ = sqrt(5).
  EXPECT_NEAR(FitPercent(y, yh), 100.0 * (1.0 - 1.0 / std::sqrt(5.0)), 1e-12);
  EXPECT_DOUBLE_EQ(FitPercent(y, y), 100.0);
  EXPECT_THROW(FitPercent(Eigen::VectorXd::Ones(4), yh), std::invalid_argument);
}

TEST(InteriorRmse, LeavesOutTheFiltersEdgeTransientAtBothEndsOfEverySegment) {
  const double ts = 1e-3, cutoff = 100.0;  // two periods of 100 Hz: 20 samples at 1 kHz
  EXPECT_EQ(FilterEdgeSamples(2000, ts, cutoff), 20);
  EXPECT_EQ(FilterEdgeSamples(100, ts, cutoff), 5);  // at most 5 % of the record
  EXPECT_EQ(FilterEdgeSamples(2000, ts, 0.0), 0);
  // What the edge is for: a controller's kick in the first sample, low-passed, has died out there.
  Eigen::VectorXd kick = Eigen::VectorXd::Zero(2000);
  kick(0) = 1000.0;
  const Eigen::VectorXd filtered = ZeroPhaseLowPass(kick, ts, cutoff);
  EXPECT_GT(filtered.head(20).cwiseAbs().maxCoeff(), 10.0);
  EXPECT_LT(filtered.segment(20, 1980).cwiseAbs().maxCoeff(), 1.0);  // 10⁻³ of the kick

  const Eigen::VectorXd measured = (2.0 * kPi * 3.0 * Time(2000, ts).array()).sin();
  Eigen::VectorXd model = measured;
  model.head(20).array() += 10.0;
  model.tail(20).array() -= 10.0;
  EXPECT_GT(Rmse(measured, model), 1.0);
  EXPECT_EQ(InteriorRmse(measured, model, {}, ts, cutoff), 0.0);
  model(20) += 1.0;  // the first sample scored
  EXPECT_DOUBLE_EQ(InteriorRmse(measured, model, {0}, ts, cutoff), std::sqrt(1.0 / 1960.0));
  // Two segments (a gap in the log at sample 1000): each has its own two edges, 20 samples of its 1000.
  model.segment(990, 30).array() += 5.0;  // the first segment's end and the second's start
  EXPECT_GT(InteriorRmse(measured, model, {0}, ts, cutoff), 0.5);
  EXPECT_DOUBLE_EQ(InteriorRmse(measured, model, {0, 1000}, ts, cutoff), std::sqrt(1.0 / 1920.0));
  EXPECT_THROW(InteriorRmse(measured, model, {5}, ts, cutoff), std::invalid_argument);
}

TEST(ResidualAutocorrelation, WhiteNoisePassesColouredFails) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  Eigen::VectorXd e(5000);
  for (auto& v : e) v = n01(rng);
  const AutocorrelationTest w = ResidualAutocorrelation(e, 20);
  EXPECT_TRUE(w.white) << "p = " << w.p_value;
  EXPECT_NEAR(w.band99, 2.58 / std::sqrt(5000.0), 1e-12);
  EXPECT_DOUBLE_EQ(w.autocorrelation(0), 1.0);
  Eigen::VectorXd c = e;
  for (Eigen::Index i = 1; i < c.size(); ++i) c(i) = 0.5 * c(i - 1) + e(i);  // AR(1)
  const AutocorrelationTest ar = ResidualAutocorrelation(c, 20);
  EXPECT_FALSE(ar.white);
  EXPECT_NEAR(ar.autocorrelation(1), 0.5, 0.05);
  EXPECT_LT(ar.p_value, 1e-10);
}

// A residual that is not a finite signal gets a message about the residual, the sample and what to check, never
// Boost's "Chi Square parameter was -nan" (issue 30).
TEST(ResidualAutocorrelation, RefusesANonFiniteOrOverflowingResidualNamingTheSample) {
  Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(200, -1.0, 1.0);
  r(17) = std::nan("");
  try {
    (void)ResidualAutocorrelation(r, 10);
    FAIL() << "a NaN residual was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("is nan at sample 17 of 200"));
    EXPECT_THAT(e.what(), HasSubstr("Check the measured column's values and unit"));
  }
  r(17) = 0.0;
  r(3) = 1e300;
  r(4) = -1e300;
  try {
    (void)ResidualAutocorrelation(r, 10);
    FAIL() << "an overflowing residual was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("overflows"));
    EXPECT_THAT(e.what(), HasSubstr("largest |r| = 1e+300"));
  }
}

TEST(InputResidualCrossCorrelation, FindsTheLagOfAnUnmodelledInputEffect) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  Eigen::VectorXd u(4000), e(4000);
  for (auto& v : u) v = n01(rng);
  for (Eigen::Index i = 0; i < e.size(); ++i) e(i) = 0.2 * n01(rng) + (i >= 3 ? 0.5 * u(i - 3) : 0.0);
  const CrossCorrelationTest x = InputResidualCrossCorrelation(u, e, 10);
  EXPECT_EQ(x.peak_lag, 3);
  EXPECT_TRUE(x.significant);
  EXPECT_GT(x.peak_value, 0.8);
}

TEST(WelchPowerSpectrum, PeakAtTheToneAndParsevalHolds) {
  const double ts = 1e-3;
  const Eigen::VectorXd t = Time(16384, ts);
  std::mt19937 rng(5);
  std::normal_distribution<double> n01;
  Eigen::VectorXd s = 2.0 * (2.0 * kPi * 125.0 * t.array()).sin();
  for (auto& v : s) v += 0.1 * n01(rng);
  const PowerSpectrum p = WelchPowerSpectrum(s, ts, 1024);
  Eigen::Index k = 0;
  p.density.maxCoeff(&k);
  EXPECT_NEAR(p.frequency_hz(k), 125.0, 1.0);
  const double df = p.frequency_hz(1) - p.frequency_hz(0);
  const double variance = (s.array() - s.mean()).square().mean();  // 2 + 0.01
  EXPECT_NEAR(p.density.sum() * df, variance, 0.03 * variance);
}

// A known FIR system y[n] = 0.5 u[n] + 0.3 u[n−1] driven by white noise: H1 is its response
// H(f) = 0.5 + 0.3 e^{−j2πf Ts} and the coherence 1; output noise leaves H1 unbiased and lowers the coherence
// where |H| is small (γ² = |H|²/(|H|² + σ²) for unit input variance).
TEST(EstimateFrequencyResponse, FindsAFirFiltersResponseAndTheNoiseInItsCoherence) {
  const double ts = 1e-3;
  const Eigen::Index n = 1 << 16;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd u(n), y(n), noisy(n);
  for (Eigen::Index i = 0; i < n; ++i) u(i) = normal(rng);
  for (Eigen::Index i = 0; i < n; ++i) {
    y(i) = 0.5 * u(i) + (i > 0 ? 0.3 * u(i - 1) : 0.0);
    noisy(i) = y(i) + 0.3 * normal(rng);
  }
  const FrequencyResponseEstimate clean = EstimateFrequencyResponse(u, y, ts, 256);
  EXPECT_EQ(clean.frequency_hz.size(), 129);
  EXPECT_NEAR(clean.frequency_hz(128), 500.0, 1e-9);
  EXPECT_GT(clean.segments, 500);
  for (Eigen::Index k = 1; k < clean.frequency_hz.size(); ++k) {
    const std::complex<double> h = 0.5 + 0.3 * std::polar(1.0, -2.0 * kPi * clean.frequency_hz(k) * ts);
    EXPECT_LT(std::abs(clean.response(k) - h), 0.02) << clean.frequency_hz(k) << " Hz";
    EXPECT_GT(clean.coherence(k), 0.98) << clean.frequency_hz(k) << " Hz";
  }
  const FrequencyResponseEstimate with_noise = EstimateFrequencyResponse(u, noisy, ts, 256);
  for (Eigen::Index k = 1; k < with_noise.frequency_hz.size(); ++k) {
    const std::complex<double> h = 0.5 + 0.3 * std::polar(1.0, -2.0 * kPi * with_noise.frequency_hz(k) * ts);
    EXPECT_LT(std::abs(with_noise.response(k) - h), 0.05) << with_noise.frequency_hz(k) << " Hz";
    const double expected = std::norm(h) / (std::norm(h) + 0.09);
    EXPECT_NEAR(with_noise.coherence(k), expected, 0.1) << with_noise.frequency_hz(k) << " Hz";
  }
  EXPECT_THROW(EstimateFrequencyResponse(u, y.head(10), ts), std::invalid_argument);
  Eigen::VectorXd bad = u;
  bad(3) = std::nan("");
  EXPECT_THROW(EstimateFrequencyResponse(bad, y, ts), std::invalid_argument);
}

// The noise floor of a residual: white noise under slow structure (a motion's band) and a narrow hum, read in the band
// above the motion's; with the residual low-passed (parallel filtering), the filtered noise's own RMS. A lower estimate
// (the quietest tenth of the segments): within [0.7, 1] × the truth, [0.5, 1] × with the few bins of a low-passed band.
TEST(EstimateNoiseFloor, RecoversTheNoiseUnderStructureWithAndWithoutTheFilter) {
  const double ts = 1e-3, sigma = 0.5;
  const Eigen::Index n = 16000;
  const Eigen::VectorXd t = Time(n, ts);
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, sigma);
  Eigen::VectorXd noise(n);
  for (Eigen::Index i = 0; i < n; ++i) noise(i) = normal(rng);
  const Eigen::VectorXd structure =
      (3.0 * (2.0 * kPi * 0.7 * t.array()).sin() + 1.5 * (2.0 * kPi * 4.0 * t.array()).sin()).matrix();
  const Eigen::VectorXd hum = (2.0 * (2.0 * kPi * 300.0 * t.array()).sin()).matrix();  // inside the upper band
  const NoiseFloor raw = EstimateNoiseFloor(structure + hum + noise, ts);
  EXPECT_GE(raw.rms, 0.7 * sigma);
  EXPECT_LE(raw.rms, 1.0 * sigma);
  EXPECT_DOUBLE_EQ(raw.band_low_hz, 250.0);
  // Low-passed at 100 Hz as compare filters an equation-error residual: the floor is the filtered noise's RMS.
  const Eigen::VectorXd filtered = ZeroPhaseLowPass(structure + noise, ts, 100.0);
  const Eigen::VectorXd filtered_noise = ZeroPhaseLowPass(noise, ts, 100.0);
  const double truth = std::sqrt(filtered_noise.squaredNorm() / static_cast<double>(n));
  const NoiseFloor low = EstimateNoiseFloor(filtered, ts, 100.0);
  EXPECT_GE(low.rms, 0.5 * truth);  // 7 bins in [25, 50] Hz per segment: measured 0.56 × the truth
  EXPECT_LE(low.rms, 1.0 * truth);
  EXPECT_DOUBLE_EQ(low.band_high_hz, 50.0);
  // Too short to tell: 0, not a guess; a band limit at Nyquist is refused.
  EXPECT_EQ(EstimateNoiseFloor(noise.head(100), ts).rms, 0.0);
  EXPECT_THROW(EstimateNoiseFloor(noise, ts, 500.0), std::invalid_argument);
}

}  // namespace
}  // namespace mb
