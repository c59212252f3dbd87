// load_scheme_probe [--out=DIR]: how far the force of a load behind a play, simulated from the logged motor motion,
// depends on how the load is stepped between the samples (issue 47). On the independent gearbox's validation record
// (the case "load behind a play" of tests/diagnosis/independent_plant.h: 25 kg behind ±0.6 mm, 18 Hz, ζ = 0.15, its
// bearing 0.6 /s) the load is simulated with the generator's own parameters from the logged position and the derived
// velocity, by three ways of reading the motor between two samples — positions and velocities each on a straight line;
// the cubic Hermite interpolant (models/physics/play_coupling.h, what the backlash_load block does); positions on a
// straight line, the velocity its chord — times two integrators (semi-implicit Euler, the classical Runge–Kutta method)
// times 1, 5, 20 and 100 sub-steps a sample. Prints, for each, the RMS of the logged force less the truth without the
// load less the simulated load's force [N], and per 0.25 s window for the converged (100 sub-step) Runge–Kutta runs.
// The generator's own re-simulation (the bench's floor, TruthForce) is the last line of that table. Then the block's own
// scheme (AdvancePlayLoad) on the training and the validation record, and beside it the same with the steps where the
// load meets or leaves a side of its play redone in 8 micro-steps (tried for the block and left out); on the training
// record, for both, the RMS left along the play's width around the truth's (the fit's surface there); and the
// validation record replayed by both from 9 copies of the logged positions each moved by less than half the log's
// count (uniform): the spread of what the same physics leaves when the load's rattle in its play turns on what the log
// cannot resolve.
// What it shows (docs/diagnosis.md, "A load behind a play"): the load's state is not measured and its impacts follow
// from the whole history, so the same physics from the same log leaves anything from 1.7 to 15 N, in episodes of a few
// seconds where the load sits against the other side of its play.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "models/physics/play_coupling.h"
#include "tests/diagnosis/independent_bench.h"

namespace {

using namespace mb;
using namespace mb::independent;

double Rms(const Eigen::VectorXd& e) { return std::sqrt(e.squaredNorm() / static_cast<double>(e.size())); }

enum class Motor { kLinearBoth, kHermite, kChord };
enum class Integrator { kSemiImplicitEuler, kRungeKutta4 };

// The load's force on the motor [N] at each sample, the load stepped by `integrator` on `sub` sub-steps a sample with
// the motor read between the samples as `motor` says.
Eigen::VectorXd LoadForce(const Eigen::VectorXd& t, const Eigen::VectorXd& x, const Eigen::VectorXd& v, Motor motor,
                          Integrator integrator, int sub) {
  constexpr double kMass = 25.0, kHalfGap = 6e-4, kZeta = 0.15, kBearing = 0.6;  // the generator's gearbox
  const double omega = 2.0 * std::numbers::pi * 18.0;
  double xl = x(0), vl = v(0);
  Eigen::VectorXd f(t.size());
  const auto acceleration = [&](double xm, double vm, double l, double lv) {
    return PlayLoadAcceleration(xm - l, vm - lv, kHalfGap, omega, kZeta) - kBearing * lv;
  };
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    f(i) = kMass * PlayLoadAcceleration(x(i) - xl, v(i) - vl, kHalfGap, omega, kZeta);
    if (i + 1 == t.size()) break;
    const double dt = t(i + 1) - t(i), h = dt / sub;
    const auto at = [&](double q, double* xm, double* vm) {
      if (motor == Motor::kHermite) return HermiteMotor(x(i), v(i), x(i + 1), v(i + 1), dt, q, xm, vm);
      *xm = x(i) + q * (x(i + 1) - x(i));
      *vm = motor == Motor::kLinearBoth ? v(i) + q * (v(i + 1) - v(i)) : (x(i + 1) - x(i)) / dt;
    };
    for (int s = 0; s < sub; ++s) {
      double xa = 0.0, va = 0.0, xb = 0.0, vb = 0.0, xc = 0.0, vc = 0.0;
      at(s / static_cast<double>(sub), &xa, &va);
      at((s + 0.5) / sub, &xb, &vb);
      at((s + 1.0) / sub, &xc, &vc);
      if (integrator == Integrator::kSemiImplicitEuler) {
        vl += h * acceleration(xa, va, xl, vl);
        xl += h * vl;
        continue;
      }
      const double a1 = acceleration(xa, va, xl, vl);
      const double a2 = acceleration(xb, vb, xl + 0.5 * h * vl, vl + 0.5 * h * a1);
      const double a3 = acceleration(xb, vb, xl + 0.5 * h * (vl + 0.5 * h * a1), vl + 0.5 * h * a2);
      const double a4 = acceleration(xc, vc, xl + h * (vl + 0.5 * h * a2), vl + h * a3);
      xl += h / 6.0 * (vl + 2.0 * (vl + 0.5 * h * a1) + 2.0 * (vl + 0.5 * h * a2) + (vl + h * a3));
      vl += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    }
  }
  return f;
}

// The load's force [N] as the backlash_load block computes it (AdvancePlayLoad: the cubic Hermite motor, Runge–Kutta 4
// on PlaySubSteps sub-steps), or with each sub-step in which the load meets or leaves a side of its play (engaged at one
// of its stages' points and not at another) redone in 8 micro-steps (refine: tried for the block and left out,
// docs/diagnosis.md "A load behind a play"). The play's half width 0.6 mm unless given.
Eigen::VectorXd BlockLoadForce(const Eigen::VectorXd& t, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                               bool refine, double half_gap = 6e-4) {
  constexpr double kMass = 25.0, kZeta = 0.15, kBearing = 0.6;  // the generator's gearbox
  constexpr int kMicroSteps = 8;
  const double omega = 2.0 * std::numbers::pi * 18.0;
  const auto acceleration = [&](double xm, double vm, double l, double lv) {
    return PlayLoadAcceleration(xm - l, vm - lv, half_gap, omega, kZeta) - kBearing * lv;
  };
  const auto engaged = [&](double xm, double l) { return std::abs(xm - l) > half_gap; };
  PlayLoad load{x(0), v(0)};
  Eigen::VectorXd f = Eigen::VectorXd::Zero(t.size());
  for (Eigen::Index i = 1; i < t.size(); ++i) {
    const double dt = t(i) - t(i - 1);
    if (!refine) {
      f(i) = kMass * AdvancePlayLoad(x(i - 1), v(i - 1), x(i), v(i), dt, half_gap, omega, kZeta, kBearing, &load);
      continue;
    }
    const auto motor = [&](double q, double* xm, double* vm) {
      HermiteMotor(x(i - 1), v(i - 1), x(i), v(i), dt, q, xm, vm);
    };
    // One Runge–Kutta step over [q0, q1] of the sample step; true when the contact changes at its stages' points.
    const auto step = [&](double q0, double q1, PlayLoad* l) {
      const double h = (q1 - q0) * dt;
      double xa, va, xb, vb, xc, vc;
      motor(q0, &xa, &va);
      motor(0.5 * (q0 + q1), &xb, &vb);
      motor(q1, &xc, &vc);
      const double x0 = l->x, v0 = l->v;
      const double a1 = acceleration(xa, va, x0, v0);
      const double x2 = x0 + 0.5 * h * v0, v2 = v0 + 0.5 * h * a1, a2 = acceleration(xb, vb, x2, v2);
      const double x3 = x0 + 0.5 * h * v2, v3 = v0 + 0.5 * h * a2, a3 = acceleration(xb, vb, x3, v3);
      const double x4 = x0 + h * v3, v4 = v0 + h * a3, a4 = acceleration(xc, vc, x4, v4);
      l->x = x0 + h / 6.0 * (v0 + 2.0 * v2 + 2.0 * v3 + v4);
      l->v = v0 + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
      const bool at_start = engaged(xa, x0);
      return engaged(xb, x2) != at_start || engaged(xb, x3) != at_start || engaged(xc, x4) != at_start ||
             engaged(xc, l->x) != at_start;
    };
    const int n = PlaySubSteps(omega, dt);
    for (int j = 0; j < n; ++j) {
      const PlayLoad before = load;
      if (!step(static_cast<double>(j) / n, (j + 1.0) / n, &load)) continue;
      load = before;
      for (int u = 0; u < kMicroSteps; ++u) {
        step((j + static_cast<double>(u) / kMicroSteps) / n, (j + (u + 1.0) / kMicroSteps) / n, &load);
      }
    }
    f(i) = kMass * PlayLoadAcceleration(x(i) - load.x, v(i) - load.v, half_gap, omega, kZeta);
  }
  return f;
}

// The smallest gap between two logged positions: the log's resolution (its encoder count) [m].
double PositionStep(const Eigen::VectorXd& x) {
  std::vector<double> sorted(x.data(), x.data() + x.size());
  std::sort(sorted.begin(), sorted.end());
  double step = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i] > sorted[i - 1]) step = std::min(step, sorted[i] - sorted[i - 1]);
  }
  return step;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = "out/load-scheme-probe";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--out=", 0) != 0) {
      std::fprintf(stderr, "load_scheme_probe: unknown argument '%s'; usage: load_scheme_probe [--out=DIR]\n", argv[i]);
      return 2;
    }
    out = a.substr(6);
  }
  CaseSpec spec;
  for (const auto& c : Cases()) {
    if (c.name == "load behind a play") spec = c;
  }
  const PreparedCase prepared = PrepareCase(spec, out);
  const MeasurementLog& log = prepared.validation;
  const std::string column = prepared.settings.measurement.position_column;
  const Eigen::VectorXd t = log.time(), x = log.column(column), v = log.column(DerivedVelocityColumn(column)),
                        a = log.column(DerivedAccelerationColumn(column)), u = log.column("force_N");
  const Eigen::VectorXd without = TruthForce(Hidden::kNone, t, x, v, a, &u);
  std::printf("| motor between samples | integrator | sub-steps | RMS left [N] |\n|---|---|---|---|\n");
  const char* motors[] = {"x and v on straight lines", "cubic Hermite (the block's)",
                          "x on a straight line, v its chord"};
  const char* integrators[] = {"semi-implicit Euler", "Runge–Kutta 4"};
  std::string windows;
  for (const Motor motor : {Motor::kLinearBoth, Motor::kHermite, Motor::kChord}) {
    for (const Integrator integrator : {Integrator::kSemiImplicitEuler, Integrator::kRungeKutta4}) {
      for (const int sub : {1, 5, 20, 100}) {
        const Eigen::VectorXd left = u - without - LoadForce(t, x, v, motor, integrator, sub);
        std::printf("| %s | %s | %d | %.3f |\n", motors[static_cast<int>(motor)],
                    integrators[static_cast<int>(integrator)], sub, Rms(left));
        if (sub != 100 || integrator != Integrator::kRungeKutta4) continue;
        windows += std::string(motors[static_cast<int>(motor)]) + ":";
        constexpr Eigen::Index kWindow = 250;
        for (Eigen::Index k = 0; k + kWindow <= left.size(); k += kWindow) {
          windows += " " + std::to_string(static_cast<int>(std::lround(Rms(left.segment(k, kWindow)))));
        }
        windows += "\n";
      }
    }
  }
  const Eigen::VectorXd with = TruthForce(Hidden::kLoadBehindPlay, t, x, v, a, &u);
  std::printf("| the generator's re-simulation (TruthForce, the bench's floor before filtering) | | | %.3f |\n",
              Rms(u - with));
  std::printf("\nRMS left per 0.25 s window [N], Runge–Kutta 4 on 100 sub-steps:\n%s", windows.c_str());

  // The block's own scheme on both records, with and without the contacts' finer steps; the training record's RMS left
  // along the play's width, the other parameters the truth's (the fit's surface a local search of the shape meets);
  // then the validation record replayed from positions that differ from the logged ones by less than the log's
  // resolution (uniform within half a count): what the same physics leaves when the load's rattle in its play is
  // decided by what the log cannot hold.
  std::printf("\n| record | the load stepped | RMS left [N] |\n|---|---|---|\n");
  std::string surfaces;
  for (const auto* record : {&prepared.training, &log}) {
    const bool training = record == &prepared.training;
    const Eigen::VectorXd rt = record->time(), rx = record->column(column),
                          rv = record->column(DerivedVelocityColumn(column)),
                          ra = record->column(DerivedAccelerationColumn(column)), ru = record->column("force_N");
    const Eigen::VectorXd rest = ru - TruthForce(Hidden::kNone, rt, rx, rv, ra, &ru);
    for (const bool refine : {false, true}) {
      std::printf("| %s | %s | %.3f |\n", training ? "training" : "validation",
                  refine ? "contact steps redone in 8 micro-steps (tried)" : "the block's: one sub-step a sample",
                  Rms(rest - BlockLoadForce(rt, rx, rv, refine)));
      if (!training) continue;
      surfaces += refine ? "contact steps redone:" : "the block's scheme:";
      for (const double gap : {1.14, 1.16, 1.18, 1.19, 1.20, 1.21, 1.22, 1.24, 1.26}) {
        surfaces += fmt::format(" {:.2f}: {:.2f};", gap, Rms(rest - BlockLoadForce(rt, rx, rv, refine, 0.5e-3 * gap)));
      }
      surfaces += "\n";
    }
  }
  std::printf("\nTraining record, the play's full width [mm] against the RMS left [N]:\n%s", surfaces.c_str());
  const double count = PositionStep(x);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> dither(-0.5 * count, 0.5 * count);
  std::vector<Eigen::VectorXd> dithered;
  for (int k = 0; k < 9; ++k) {
    Eigen::VectorXd xd = x;
    for (Eigen::Index i = 0; i < xd.size(); ++i) xd(i) += dither(rng);
    dithered.push_back(std::move(xd));
  }
  for (const bool refine : {false, true}) {
    std::vector<double> replays;
    for (const Eigen::VectorXd& xd : dithered) replays.push_back(Rms(u - without - BlockLoadForce(t, xd, v, refine)));
    std::vector<double> sorted = replays;
    std::sort(sorted.begin(), sorted.end());
    std::printf("\nThe validation record replayed (%s) from positions within half a count (%.3g) of the logged ones, "
                "9 draws [N]:", refine ? "contact steps redone" : "the block's scheme", count);
    for (const double r : replays) std::printf(" %.2f", r);
    std::printf("; median %.2f, from %.2f to %.2f\n", sorted[4], sorted.front(), sorted.back());
  }
  return 0;
}
