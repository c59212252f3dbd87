// The factors of the diagnosis grammar and what their proposal rules share (factors.h). Sources: DIAGNOSIS.md, "Beyond
// the catalogue"; Brunton, Proctor & Kutz 2016 (SINDy's library of products); VanderPlas 2018 (Lomb–Scargle).
#include "models/diagnosis/factors.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <boost/math/tools/minima.hpp>
#include <fmt/format.h>

#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/periodogram.h"

namespace mb {

namespace {

// The squared correlation of a and b (0 when either is constant).
double SquaredCorrelation(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::ArrayXd da = a.array() - a.mean(), db = b.array() - b.mean();
  const double saa = da.square().sum(), sbb = db.square().sum();
  if (!(saa > 0.0 && sbb > 0.0)) return 0.0;
  const double sab = (da * db).sum();
  return sab * sab / (saa * sbb);
}

}  // namespace

const char* UnreadColumnDuplicate(const DiagnosisSignals& s, std::size_t k) {
  const Eigen::VectorXd& column = s.extra_columns.at(k);
  const std::pair<const char*, const Eigen::VectorXd*> read[] = {
      {"the compared output (the logged command)", &s.logged_command}, {"the position", &s.position},
      {"the velocity", &s.velocity}};
  for (const auto& [what, signal] : read) {
    if (signal->size() == column.size() && SquaredCorrelation(column, *signal) >= kDuplicateColumnCorrelation) {
      return what;
    }
  }
  return nullptr;
}

const Eigen::VectorXd& UnreadColumn(const EffectInstance& e, const DiagnosisSignals& s) {
  const double k = RequiredParameter(e, "column");
  if (!(k >= 0.0 && k < static_cast<double>(s.extra_columns.size()) && k == std::floor(k))) {
    throw std::invalid_argument(fmt::format(
        "effect '{}': column {} is not one of the log's {} column(s) that the diagram does not read; a record carried "
        "to another must hold the same extra columns",
        e.name, k, s.extra_columns.size()));
  }
  return s.extra_columns[static_cast<std::size_t>(k)];
}

Eigen::VectorXd Centered(const Eigen::VectorXd& column) {
  return (column.array() - (column.size() > 0 ? column.mean() : 0.0)).matrix();
}

double BestSlipVelocity(const ProposalContext& c,
                        const std::function<Eigen::MatrixXd(const Eigen::VectorXd& slip)>& columns) {
  constexpr int kOctaves = 5;
  const Eigen::MatrixXd base = c.BaseWithConstant();  // JointFitResidual keeps a reference
  const JointFitResidual fit(base, c.residual(), c.loop());
  // The residual left at v_s = dead_band·2^−k, k real (the octave below the dead band).
  const auto sse_at = [&](double k) {
    return fit(columns((c.signals().velocity.array() / (c.dead_band() * std::exp2(-k))).tanh().matrix()));
  };
  int best = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kOctaves; ++k) {
    const double sse = sse_at(k);
    if (sse < best_sse) {
      best_sse = sse;
      best = k;
    }
  }
  // Then between the grid points beside the best (Brent's minimiser in log₂ v_s; 6 bits: it stops within ≈ 3 % of
  // the octave index, ≤ 0.16 octave, or after 8 fits): `improve` keeps the slip velocity it is given, and the grid's
  // factor of 2 left grammar draw 88's drifting Coulomb level 1.36 × its floor.
  constexpr int kBits = 6;
  std::uintmax_t iterations = 8;
  const auto [k, sse] = boost::math::tools::brent_find_minima(
      sse_at, std::max(0.0, best - 1.0), std::min<double>(kOctaves, best + 1.0), kBits, iterations);
  return c.dead_band() * std::exp2(-(sse < best_sse ? k : static_cast<double>(best)));
}

Eigen::VectorXd Bump(const Eigen::VectorXd& position, double center, double half_width) {
  return position.unaryExpr([&](double x) {
    const double z = (x - center) / half_width;
    if (!(std::abs(z) < 1.0)) return 0.0;
    const double c = std::cos(0.5 * std::numbers::pi * z);
    return c * c;
  });
}

Eigen::VectorXd BumpSlope(const Eigen::VectorXd& position, double center, double half_width) {
  return position.unaryExpr([&](double x) {
    const double z = (x - center) / half_width;
    return std::abs(z) < 1.0 ? -0.5 * std::numbers::pi / half_width * std::sin(std::numbers::pi * z) : 0.0;
  });
}

int MotionHarmonic(const ProposalContext& c, double f) {
  const double motion_hz = c.search().motion_frequency_hz;
  if (!(motion_hz > 0.0)) return 0;
  const double k = std::round(f / motion_hz);
  return k >= 1.0 && k <= c.options().motion_harmonics && std::abs(f - k * motion_hz) <= 0.01 * f ? static_cast<int>(k)
                                                                                                  : 0;
}

std::optional<Periodogram> DemodulatedPeriodogram(const ProposalContext& c, const Eigen::VectorXd& abscissa,
                                                  const Eigen::VectorXd& modulation, PeriodogramOptions options) {
  const DiagnosisSignals& s = c.signals();
  const Eigen::Index n = c.size();
  if (modulation.size() != n || abscissa.size() != n) return std::nullopt;
  std::vector<double> magnitude;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (std::abs(s.velocity(i)) > c.dead_band()) magnitude.push_back(std::abs(modulation(i)));
  }
  if (magnitude.size() < 256) return std::nullopt;
  const auto middle = magnitude.begin() + static_cast<std::ptrdiff_t>(magnitude.size() / 2);
  std::nth_element(magnitude.begin(), middle, magnitude.end());
  const double floor = std::max(*middle, 1e-300);
  std::vector<double> x, d;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (std::abs(s.velocity(i)) > c.dead_band() && std::abs(modulation(i)) >= floor) {
      x.push_back(abscissa(i));
      d.push_back(c.residual()(i) / modulation(i));
    }
  }
  if (x.size() < 256) return std::nullopt;
  const Eigen::Map<const Eigen::VectorXd> xs(x.data(), static_cast<Eigen::Index>(x.size()));
  const Eigen::Map<const Eigen::VectorXd> ds(d.data(), static_cast<Eigen::Index>(d.size()));
  try {
    return LombScarglePeriodogram(xs, ds, options);
  } catch (const std::invalid_argument&) {
    return std::nullopt;  // an empty period range (a stroke of a few steps), a constant residual: nothing to propose
  }
}

std::optional<ProposedPeriod> ModulatedPeriod(const ProposalContext& c, const Eigen::VectorXd& modulation) {
  if (!(c.position_span() > 0.0)) return std::nullopt;
  PeriodogramOptions options = c.options().position_periodogram;
  options.max_period = c.position_span() / c.options().min_position_cycles_with_harmonics;
  const std::optional<Periodogram> pg = DemodulatedPeriodogram(c, c.signals().position, modulation, options);
  if (!pg) return std::nullopt;
  for (std::size_t i = 0; i < pg->peaks.size(); ++i) {
    const PeriodogramPeak& p = pg->peaks[i];
    if (p.harmonic_of >= 0 || !p.significant) continue;
    return ProposedPeriod{p.period, HarmonicCount(*pg, i, c.options().max_harmonics), p.power};
  }
  return std::nullopt;
}

BumpPlace ScanBump(const ProposalContext& c, const Eigen::VectorXd& m, const Eigen::VectorXd* kinetic) {
  const DiagnosisSignals& s = c.signals();
  BumpPlace best;
  const double span = c.position_span();
  if (!(span > 0.0)) return best;
  const double x_min = s.position.minCoeff();
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const Eigen::MatrixXd gram = base.transpose() * base;
  const JointFitResidual fit(base, gram, c.residual(), c.loop());
  const double sse_base = fit(Eigen::MatrixXd(c.size(), 0));
  if (!(sse_base > 0.0)) return best;
  double best_sse = sse_base;
  const auto bump_column = [&](double center, double half_width) {  // m·g(x), plus ½v²·g′(x) for a mass (Lagrange)
    Eigen::VectorXd column = m.cwiseProduct(Bump(s.position, center, half_width));
    if (kinetic != nullptr) column += kinetic->cwiseProduct(BumpSlope(s.position, center, half_width));
    return column;
  };
  constexpr double kWidest = 1.0 / 10.0;  // of the travel: a wider stretch is not one place
  for (const double fraction : {1.0 / 40.0, 1.0 / 20.0, kWidest}) {
    const double w = fraction * span;
    // The stretch lies inside the travel with room on both sides, so that the axis passes through it: at an end a
    // bump is confounded with the reversals there.
    for (double center = x_min + 2.0 * w; center <= x_min + span - 2.0 * w; center += 0.5 * w) {
      const Eigen::VectorXd column = bump_column(center, w);
      if (!(column.squaredNorm() > 0.0)) continue;
      const double sse = fit(column);
      if (sse < best_sse) {
        best_sse = sse;
        best = {center, w, 1.0 - sse / sse_base};
      }
    }
  }
  if (!(best.half_width > 0.0)) return best;
  // The grid's place refined coordinate-wise: the centre within ± w/2, the half-width within [w/√2, √2·w] (at most
  // the widest of the grid: on EMPS a damping 35 mm either side of 45 mm, a seventh of the travel, came before the
  // screw lead), the centre again.
  const auto sse_at = [&](double center, double half_width) {
    const Eigen::VectorXd column = bump_column(center, half_width);
    return column.squaredNorm() > 0.0 ? fit(column) : sse_base;
  };
  constexpr int kBits = 20;  // of the precision within the bracket: far below the encoder's step
  const auto minimum = [](const auto& sse_of, double lo, double hi) {  // Brent's {argument, sse} over [lo, hi]
    boost::uintmax_t iterations = 40;
    return boost::math::tools::brent_find_minima(sse_of, lo, hi, kBits, iterations);
  };
  const auto keep_if_better = [&](double center, double half_width, double sse) {
    if (!(sse < best_sse)) return;
    best_sse = sse;
    best = {center, half_width, 1.0 - sse / sse_base};
  };
  const auto refine_center = [&] {
    const double x0 = best.center, w = best.half_width;
    const auto [center, sse] = minimum([&](double x) { return sse_at(x, w); }, x0 - 0.5 * w, x0 + 0.5 * w);
    keep_if_better(center, w, sse);
  };
  const auto refine_half_width = [&] {
    const double x0 = best.center, w = best.half_width;
    const auto [half_width, sse] = minimum([&](double h) { return sse_at(x0, h); }, w / std::numbers::sqrt2,
                                           std::min(w * std::numbers::sqrt2, kWidest * span));
    keep_if_better(x0, half_width, sse);
  };
  refine_center();
  refine_half_width();
  refine_center();
  return best;
}

std::optional<ProposedPeriod> RippleASmoothFunctionWouldBlur(const ProposalContext& c) {
  constexpr double kMinCycles = 16.0;      // in the travel: a ripple, not a smooth function
  constexpr double kMinRippleShare = 0.02;  // of the residual's variance
  for (const auto& p : c.position_periods()) {
    if (p.period <= c.position_span() / kMinCycles && p.power >= kMinRippleShare) return p;
  }
  return std::nullopt;
}

}  // namespace mb
