// backlash_load: a load behind a play (gear backlash between a motor and its load, the motor's position logged): while
// the play is open the motor carries its own inertia only, then the load engages with an impact and rings at the
// shaft's mode. The drive-train benchmark's two-mass model with a dead zone (models/physics/play_coupling.h), its load
// simulated from the logged motor motion: x_L(0) = x(0), ẍ_L = PlayLoadAcceleration(x − x_L, v − v_L, g/2, ω, ζ) −
// β·v_L, stepped from sample to sample by AdvancePlayLoad.
// Regressor: the shaft's force per unit load mass, its coefficient the load mass m_L [kg, kg·m² on a rotary axis]
// {backlash g [m], frequency_hz f [Hz], damping_ratio ζ, load_damping β [1/s]}.
// Proposal (the joint fit's output error over the four shape parameters; Propose says why in three stages): a grid of
// the play, the load's own damping β and the mode on the record's first kGridSamples, local searches of all four from
// its best points on the first kScanSamples, then a lattice of f, ζ and β around that and local searches again, each
// fit without the derived motion's edge transients (ProposalContext::edge_samples; the load still simulated from the
// record's start). The
// fit's surface is ragged (each impact's time and strength follow from the whole history of the load in its play); the
// coefficient is fitted on the whole record by the selection, and a negative one (no load pulls the motor along) is
// worth nothing in the search. A best gap at either end of the grid is not a play (the smallest: the plain mode, which
// resonance models; the widest: a force along the travel). A load that rattles in its play while the motor rests (it
// bounces off a side at least once a dwell with the shape found) is said to: its held-out error is then a draw
// (docs/diagnosis.md, "A load behind a play"). Block: backlash_load on the position and velocity, the same scheme.
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <numeric>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlopt.hpp>
#include <tbb/parallel_for.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/signal_processing.h"
#include "models/physics/play_coupling.h"

namespace mb {
namespace {

constexpr const char* kName = "backlash_load";
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The gap's grid, as backlash's (effects/backlash.cc): below 0.25 % of the travel a play is crossed within a few
// samples of each reversal and the term is the plain mode.
constexpr double kGapLow = 0.0025, kGapHigh = 0.05;
constexpr int kGapGrid = 20, kLoadDampingGrid = 16, kFrequencyGrid = 6;
constexpr double kGridDampingRatio = 0.2;                              // ζ during the grid (see Propose)
constexpr double kLoadDampingGridLow = 0.1, kLoadDampingGridHigh = 30.0;  // β's grid [1/s]
constexpr double kModeLow = 2.0, kModeHigh = 200.0;  // [Hz]: the mode's range (at most an eighth of the sample rate)
constexpr double kDampingLow = 0.005, kDampingHigh = 0.7;           // ζ's bounds in the local searches
constexpr double kLoadDampingLow = 0.01, kLoadDampingHigh = 100.0;  // β's [1/s]
constexpr int kStarts = 3, kLocalEvaluations = 120;  // local searches from a stage's best points, each's budget
// The share of the residual's sum of squares the grid's best must explain for the local searches to run: below it no
// load is there (the searches are most of the proposal's cost, and a record without the load is the usual one).
constexpr double kMinGridShare = 0.05;
// The shape is searched on the record's first samples (its coefficient is fitted on the whole record): each trial
// simulates the load through them, and the search runs ~1000 trials.
constexpr Eigen::Index kScanSamples = 20000, kGridSamples = 3000;
// The grid's loads stepped side by side at one mode (MotorPath::LoadAccelerations).
constexpr std::size_t kLanes = 4;

// ẍ_L at the first n samples [m/s²]: the load behind the play simulated from the logged motor motion, starting with
// the motor's (AdvancePlayLoad; the backlash_load block steps the same way).
Eigen::VectorXd LoadAcceleration(const DiagnosisSignals& s, Eigen::Index n, double gap, double f_hz, double zeta,
                                 double beta) {
  const Eigen::VectorXd& x = s.position;
  const Eigen::VectorXd& v = s.velocity;
  const double w = kTwoPi * f_hz, half = 0.5 * gap;
  Eigen::VectorXd out(n);
  if (n == 0) return out;
  PlayLoad load{x(0), v(0)};
  out(0) = 0.0;
  for (Eigen::Index i = 1; i < n; ++i) {
    out(i) = AdvancePlayLoad(x(i - 1), v(i - 1), x(i), v(i), s.time(i) - s.time(i - 1), half, w, zeta, beta,
                             &load);
  }
  return out;
}

// The motor's path through the first n samples as the load's Runge–Kutta steps read it at the mode ω: each step's start
// and each sub-step's middle and end (PlayMotorAtSubStep). The grid tries 320 plays and bearings at each of its modes;
// stored once per mode, the path spares every trial the interpolant's arithmetic, and its loads are stepped kLanes at a
// time, each the one LoadAcceleration simulates, to the last bit.
class MotorPath {
 public:
  MotorPath() = default;
  MotorPath(const DiagnosisSignals& s, Eigen::Index n, double f_hz) : omega_(kTwoPi * f_hz), n_(n) {
    const Eigen::VectorXd& x = s.position;
    const Eigen::VectorXd& v = s.velocity;
    steps_.assign(static_cast<std::size_t>(std::max<Eigen::Index>(n, 1)), 0);
    first_.assign(steps_.size(), 0);
    start_.assign(2 * steps_.size(), 0.0);
    for (Eigen::Index i = 1; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      const double dt = s.time(i) - s.time(i - 1);
      steps_[k] = PlaySubSteps(omega_, dt);
      first_[k] = points_.size();
      HermiteMotor(x(i - 1), v(i - 1), x(i), v(i), dt, 0.0, &start_[2 * k], &start_[2 * k + 1]);
      for (int j = 0; j < steps_[k]; ++j) {
        double mid[2], end[2];
        PlayMotorAtSubStep(x(i - 1), v(i - 1), x(i), v(i), dt, steps_[k], j, mid, end);
        points_.insert(points_.end(), {mid[0], mid[1], end[0], end[1]});
      }
    }
  }

  // ẍ_L at the path's samples [m/s²] for K loads at its mode (column k: shape k's, as LoadAcceleration(s, n, g, f, ζ, β)
  // gives it, to the last bit), stepped side by side (StepPlayLoads).
  template <int K>
  Eigen::MatrixXd LoadAccelerations(const DiagnosisSignals& s, const PlayLoadShape (&shape)[K]) const {
    Eigen::MatrixXd out(n_, K);
    if (n_ == 0) return out;
    PlayLoad load[K];
    for (int k = 0; k < K; ++k) load[k] = {s.position(0), s.velocity(0)};
    out.row(0).setZero();
    for (Eigen::Index i = 1; i < n_; ++i) {
      const std::size_t at = static_cast<std::size_t>(i);
      const double* p = points_.data() + first_[at];
      StepPlayLoads(
          steps_[at], (s.time(i) - s.time(i - 1)) / steps_[at], start_[2 * at], start_[2 * at + 1],
          [p](int j, double* mid, double* end) {
            mid[0] = p[4 * j];
            mid[1] = p[4 * j + 1];
            end[0] = p[4 * j + 2];
            end[1] = p[4 * j + 3];
          },
          omega_, shape, load);
      for (int k = 0; k < K; ++k) {
        out(i, k) = PlayLoadAcceleration(s.position(i) - load[k].x, s.velocity(i) - load[k].v, shape[k].half_gap,
                                         omega_, shape[k].zeta);
      }
    }
    return out;
  }

 private:
  double omega_ = 0.0;
  Eigen::Index n_ = 0;
  std::vector<int> steps_;           // per sample i ≥ 1: the sub-steps from sample i − 1 to i
  std::vector<std::size_t> first_;   // per sample: where its sub-steps' points begin in points_
  std::vector<double> start_;        // per sample: the motor at the step's start (position, velocity)
  std::vector<double> points_;       // per sub-step: the middle's position and velocity, the end's
};

// The shape of the load behind the play: everything but its mass.
struct Shape {
  double gap, frequency_hz, damping_ratio, load_damping;  // [m], [Hz], [-], [1/s]
};

// The joint fit's SSE of a shape, a pure function of it (the grid and the local searches run it concurrently).
using ShapeCost = std::function<double(const Shape&)>;
using Trial = std::pair<Shape, double>;  // a shape and its cost

std::vector<double> LogOf(const Shape& s) {
  return {std::log(s.gap), std::log(s.frequency_hz), std::log(s.damping_ratio), std::log(s.load_damping)};
}

Shape ShapeOfLog(const double* y) { return {std::exp(y[0]), std::exp(y[1]), std::exp(y[2]), std::exp(y[3])}; }

// A local search of the four shape parameters together, in log, from `start` within [lo, hi] (Subplex,
// derivative-free: the fit moves in steps as an impact crosses a sample; Rowan 1990, NLopt's LN_SBPLX). The fit's
// valleys run along diagonals (a wider play met by a stiffer shaft engages at about the same time), where one
// parameter at a time crawls.
Trial LocalSearch(const ShapeCost& cost, const Shape& start, const Shape& lo, const Shape& hi) {
  nlopt::opt opt(nlopt::LN_SBPLX, 4);
  const std::vector<double> lower = LogOf(lo), upper = LogOf(hi);
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_initial_step(std::vector<double>{0.15, 0.08, 0.3, 0.5});
  opt.set_xtol_abs(1e-4);
  opt.set_maxeval(kLocalEvaluations);
  opt.set_min_objective(
      [](unsigned, const double* y, double*, void* data) {
        return (*static_cast<const ShapeCost*>(data))(ShapeOfLog(y));
      },
      const_cast<ShapeCost*>(&cost));
  std::vector<double> y = LogOf(start);
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = std::clamp(y[k], lower[k], upper[k]);
  double best = 0.0;
  try {
    opt.optimize(y, best);
  } catch (const nlopt::roundoff_limited&) {  // y holds the best point reached
  }
  return {ShapeOfLog(y.data()), cost(ShapeOfLog(y.data()))};
}

bool Cheaper(const Trial& a, const Trial& b) { return a.second < b.second; }

// A load that rattles in its play while the motor rests: its contacts per dwell (the stretches of at least
// kMinDwellSamples samples with |v| under the dead band) with the shape found, when they average kRattleContacts or more
// (it bounces off a side at least once a dwell), else 0. The load is simulated with the shape from
// the record's start; a contact is a sample where the shaft carries a force (PlayLoadAcceleration ≠ 0).
constexpr Eigen::Index kMinDwellSamples = 20;
constexpr double kRattleContacts = 2.0;
double RattleContactsPerDwell(const ProposalContext& c, const Shape& shape) {
  const DiagnosisSignals& s = c.signals();
  const Eigen::VectorXd load =
      LoadAcceleration(s, s.size(), shape.gap, shape.frequency_hz, shape.damping_ratio, shape.load_damping);
  Eigen::Index dwells = 0, contacts = 0, run = 0, run_contacts = 0;
  const auto end_of_run = [&] {
    if (run >= kMinDwellSamples) {
      ++dwells;
      contacts += run_contacts;
    }
    run = run_contacts = 0;
  };
  for (Eigen::Index i = 1; i < s.size(); ++i) {
    if (std::abs(s.velocity(i)) < c.dead_band()) {
      ++run;
      run_contacts += (load(i) != 0.0) != (load(i - 1) != 0.0) ? 1 : 0;
    } else {
      end_of_run();
    }
  }
  end_of_run();  // a record that ends at rest: its last dwell counts too
  if (dwells == 0) return 0.0;
  const double per_dwell = static_cast<double>(contacts) / static_cast<double>(dwells);
  return per_dwell >= kRattleContacts ? per_dwell : 0.0;
}

// Each trial's cost, concurrently.
std::vector<Trial> Evaluate(const std::vector<Shape>& trials, const ShapeCost& cost) {
  std::vector<Trial> out(trials.size());
  tbb::parallel_for(std::size_t{0}, trials.size(), [&](std::size_t k) { out[k] = {trials[k], cost(trials[k])}; });
  return out;
}

// Local searches from the kStarts best trials, concurrently; the best point found.
Trial SearchFrom(std::vector<Trial> trials, const ShapeCost& cost, const Shape& lo, const Shape& hi) {
  const std::size_t starts = std::min<std::size_t>(kStarts, trials.size());
  std::partial_sort(trials.begin(), trials.begin() + static_cast<std::ptrdiff_t>(starts), trials.end(), Cheaper);
  std::vector<Trial> found(starts);
  tbb::parallel_for(std::size_t{0}, starts,
                    [&](std::size_t k) { found[k] = LocalSearch(cost, trials[k].first, lo, hi); });
  return *std::min_element(found.begin(), found.end(), Cheaper);
}

// Whether the shape's gap is one of its own (true), or at an end of the grid [g_lo, g_hi]: the smallest is the plain
// two-mass mode (resonance) or the friction law at reversals, the widest a force along the travel; noted (false).
bool IsAPlay(ProposalContext& c, const Shape& shape, double g_lo, double g_hi) {
  if (shape.gap < 1.05 * g_lo) {
    c.Note(fmt::format("{} not proposed: the joint fit's best play is the smallest tried ({:.3g}, {} % of the travel) "
                       "with the load ringing at {:.4g} Hz: a load without play (resonance), not one behind a play",
                       kName, shape.gap, 100.0 * kGapLow, shape.frequency_hz));
    return false;
  }
  if (shape.gap > 0.95 * g_hi) {
    c.Note(fmt::format("{} not proposed: the joint fit's best play is the widest tried ({:.3g}, {} % of the travel): "
                       "a force that changes along the travel rather than a load engaging after each reversal",
                       kName, shape.gap, 100.0 * kGapHigh));
    return false;
  }
  return true;
}

void Propose(ProposalContext& c) {
  if (!(c.max_speed() > 0.0) || !(c.position_span() > 0.0)) return;
  const DiagnosisSignals& s = c.signals();
  const double ts = c.sample_period();
  const double f_lo = kModeLow;
  const double band = c.options().band_limit_hz > 0.0 ? 0.5 * c.options().band_limit_hz : 0.125 / ts;
  const double f_hi = std::min(kModeHigh, band);
  const double g_lo = kGapLow * c.position_span(), g_hi = kGapHigh * c.position_span();
  if (!(f_lo < f_hi)) return;
  // The local searches' window, and the grid's shorter one. In simulation mode the loop's response is of the whole
  // record: both run on all of it.
  const bool whole = c.loop() != nullptr;
  const Eigen::Index n = whole ? c.size() : std::min<Eigen::Index>(c.size(), kScanSamples);
  const Eigen::Index n_grid = whole ? c.size() : std::min<Eigen::Index>(c.size(), kGridSamples);
  // The derived motion's edge transients are left out of every fit: on a sweep that opens with the controller's kick
  // (−600 N against a load of 8 N), the kick outweighed the load on the grid's samples (memory draw 2000036: 1.9 %).
  const Eigen::Index edge = c.edge_samples(), size = c.size();
  const Eigen::MatrixXd base = WithoutEdges<Eigen::MatrixXd>(c.BaseWithConstant().topRows(n), edge, size);
  const Eigen::MatrixXd base_grid = WithoutEdges<Eigen::MatrixXd>(base.topRows(n_grid), edge, size);
  const Eigen::VectorXd residual = WithoutEdges<Eigen::VectorXd>(c.residual().head(n), edge, size);
  const Eigen::VectorXd residual_grid = WithoutEdges<Eigen::VectorXd>(residual.head(n_grid), edge, size);
  const JointFitResidual joint_fit(base, residual, c.loop()), grid_fit(base_grid, residual_grid, c.loop());
  // A shape's fit, worth nothing where the load's mass comes out negative (no load pulls the motor along).
  const auto fit_of = [&](const JointFitResidual& fit, double sse_without, const Eigen::VectorXd& load) {
    Eigen::VectorXd mass;
    const double sse = fit(WithoutEdges<Eigen::VectorXd>(load, edge, size), &mass);
    return mass(0) > 0.0 ? sse : sse_without;
  };
  const double residual_sse = residual.squaredNorm(), grid_residual_sse = residual_grid.squaredNorm();
  const ShapeCost cost = [&](const Shape& k) {
    return fit_of(joint_fit, residual_sse,
                  LoadAcceleration(s, n, k.gap, k.frequency_hz, k.damping_ratio, k.load_damping));
  };
  const Shape lo{0.5 * g_lo, f_lo, kDampingLow, kLoadDampingLow}, hi{g_hi, f_hi, kDampingHigh, kLoadDampingHigh};
  // 1. A grid of the play, the load's own damping and the mode, on the record's first kGridSamples, and local searches
  //    of all four from its best points on kScanSamples. After each reversal the load coasts across its play, slowed
  //    by its bearing: the gap and β set when it meets the other side, and 20 % off in either loses most of the fit
  //    (on the grammar's draws with a load); the mode and its damping ratio are forgiving (20 % off in f keeps most).
  std::vector<Shape> grid;
  // In simulation mode each trial runs through the loop over the whole record: half the grid's points each way.
  const int coarser = whole ? 2 : 1;
  const std::vector<double> modes = LogSpaced(f_lo, f_hi, kFrequencyGrid / coarser);
  for (double gap : LogSpaced(g_lo, g_hi, kGapGrid / coarser)) {
    for (double beta : LogSpaced(kLoadDampingGridLow, kLoadDampingGridHigh, kLoadDampingGrid / coarser)) {
      for (double f : modes) grid.push_back({gap, f, kGridDampingRatio, beta});
    }
  }
  // The grid's trials at each mode in groups of kLanes (a group's last short one padded with its last trial), each
  // group's loads simulated together on the mode's motor path; the costs in the grid's order.
  std::vector<std::vector<std::size_t>> groups;
  for (double f : modes) {
    std::vector<std::size_t> at_mode;
    for (std::size_t t = 0; t < grid.size(); ++t) {
      if (grid[t].frequency_hz == f) at_mode.push_back(t);
    }
    for (std::size_t first = 0; first < at_mode.size(); first += kLanes) {
      groups.emplace_back(at_mode.begin() + static_cast<std::ptrdiff_t>(first),
                          at_mode.begin() + static_cast<std::ptrdiff_t>(std::min(first + kLanes, at_mode.size())));
    }
  }
  std::vector<MotorPath> paths(modes.size());  // the motor's path at each of the grid's modes, in the order of `modes`
  tbb::parallel_for(std::size_t{0}, modes.size(), [&](std::size_t m) { paths[m] = MotorPath(s, n_grid, modes[m]); });
  std::vector<Trial> on_grid(grid.size());
  tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
    const std::vector<std::size_t>& group = groups[g];
    PlayLoadShape shapes[kLanes];
    for (std::size_t k = 0; k < kLanes; ++k) {
      const Shape& trial = grid[group[std::min(k, group.size() - 1)]];
      shapes[k] = {0.5 * trial.gap, trial.damping_ratio, trial.load_damping};
    }
    const std::size_t mode = static_cast<std::size_t>(
        std::find(modes.begin(), modes.end(), grid[group.front()].frequency_hz) - modes.begin());
    const Eigen::MatrixXd loads = paths[mode].LoadAccelerations(s, shapes);
    for (std::size_t k = 0; k < group.size(); ++k) {
      on_grid[group[k]] = {grid[group[k]], fit_of(grid_fit, grid_residual_sse, loads.col(static_cast<Eigen::Index>(k)))};
    }
  });
  const Trial grid_best = *std::min_element(on_grid.begin(), on_grid.end(), Cheaper);
  if (!(grid_best.second < (1.0 - kMinGridShare) * grid_residual_sse)) {
    c.Note(fmt::format("{} not proposed: a load behind a play (of a positive mass) explains {:.1f} % of the residual "
                       "(under {:.0f} %) on the grid of its play, its damping and its mode", kName,
                       100.0 * (1.0 - grid_best.second / grid_residual_sse), 100.0 * kMinGridShare));
    return;
  }
  if (!IsAPlay(c, grid_best.first, g_lo, g_hi)) return;
  const Trial coarse = SearchFrom(on_grid, cost, lo, hi);
  // 2. The ring: a lattice of f (±20 % in 2.5 % steps), ζ and β around that fit, its gap kept, then local searches.
  //    A lightly damped ring's fit is a narrow valley: 2 % off in f triples its error on the independent gearbox.
  std::vector<Shape> lattice;
  for (double qf = 0.85; qf < 1.24; qf *= 1.025) {
    for (double zeta : {0.06, 0.1, 0.15, 0.22}) {
      for (double qb : {0.5, 1.0, 2.0}) {
        lattice.push_back({coarse.first.gap, std::clamp(coarse.first.frequency_hz * qf, f_lo, f_hi), zeta,
                           std::clamp(coarse.first.load_damping * qb, kLoadDampingLow, kLoadDampingHigh)});
      }
    }
  }
  const Trial ring = SearchFrom(Evaluate(lattice, cost), cost, lo, hi);
  const Shape best = ring.second < coarse.second ? ring.first : coarse.first;
  if (!IsAPlay(c, best, g_lo, g_hi)) return;
  if (const double rattle = RattleContactsPerDwell(c, best); rattle > 0.0) {
    c.Note(fmt::format("{}: the load rattles in its play while the motor rests ({:.1f} changes of contact per dwell "
                       "with the shape found): where it comes to rest, and when the next move meets it, turns on "
                       "sub-micrometre detail of the motion, so any simulation of it, the block's too, meets some "
                       "impacts early or late on another record, and its held-out error varies from record to record "
                       "(gear rattle; following it needs the load's state, which the log does not hold)",
                       kName, rattle));
  }
  c.Propose(kName, {{"backlash", best.gap},
                    {"frequency_hz", best.frequency_hz},
                    {"damping_ratio", best.damping_ratio},
                    {"load_damping", best.load_damping}});
}

EffectType BacklashLoad() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 101;
  t.physics = "a load behind a play (gear backlash between the motor and its load): after each reversal the motor "
              "moves its own inertia across the gap, then the load engages with an impact and rings at the shaft's "
              "mode; add a backlash_load block on the position and velocity";
  t.regressor_formula = "ẍ_L of the load behind the play, simulated from the measured x, v";
  t.parameters = {{"backlash", "m", "g: the play's full width between motor and load"},
                  {"frequency_hz", "Hz", "f: the engaged shaft's mode, √(k/m_L)/2π"},
                  {"damping_ratio", "", "ζ: the engaged shaft's damping ratio"},
                  {"load_damping", "1/s", "β = b_L/m_L: the load's own viscous friction per unit mass"},
                  {"load_mass", "kg", "m_L: the load's mass (its inertia on a rotary axis), the fitted coefficient"}};
  t.traits.coefficient_parameter = "load_mass";
  t.traits.positive_coefficient = true;
  t.traits.positive_because = "it is the load's mass";
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const double f = PositiveParameter(e, "frequency_hz");
    const double gap = RequiredParameter(e, "backlash");
    if (!(gap >= 0.0)) {
      throw std::invalid_argument(fmt::format("effect '{}': backlash = {} must be >= 0", e.name, gap));
    }
    EffectRegressors out;
    out.columns = LoadAcceleration(s, s.size(), gap, f, PositiveParameter(e, "damping_ratio"),
                                   RequiredParameter(e, "load_damping"));
    out.column_names = {e.name + ".load_mass"};
    return out;
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(backlash_load, mb::BacklashLoad())
