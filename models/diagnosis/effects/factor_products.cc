// The products of the diagnosis grammar (factors.h): a factor of the position — periodic, cos/sin(2πkx/P) for
// k = 1..K, or local, a bump over [c − w, c + w] — times a factor of the motion or the force — 1, the direction of
// slip tanh(v/v_s), ŷ. One mechanism, one table row per product, each named in the field's words (docs/diagnosis.md,
// "The grammar"):
//   friction_ripple        slip(v) × periodic(x)  friction that varies along the pitch (magnetic attraction, preload,
//                                                 a wavy guide) {period P [m], harmonics K, slip_velocity v_s [m/s]}
//   force_constant_ripple  ŷ × periodic(x)        the force constant ripples with position (force/torque ripple)
//                                                 {period P, harmonics K}; equation-error mode: ŷ is the model's force
//                                                 from the measured motion, never the logged (compared) command
//   local_friction         slip(v) × bump(x)      friction at one place (a damaged spot, a seal, debris)
//                                                 {center c, half_width w [m], slip_velocity v_s}
//   damping_ripple         v × periodic(x)        the damping varies along the pitch (back-EMF constant, eddy currents)
//   inertia_ripple         a × periodic(x)        the moving mass varies with position (an arm, a linkage, a cam):
//                                                 a mass M(x) acts as M(x)·a + ½M′(x)·v² (Lagrange; InertiaColumns)
//   local_damping          v × bump(x)            viscous drag at one place (a wiper, a seal, thicker grease)
//   column_damping         v × (c − c̄)            the viscous friction follows an unread log column c (the lubricant's
//                                                 temperature) {column: its index in DiagnosisSignals::extra_columns}
//   friction_along_travel  slip(v) × smooth(x)    friction that changes smoothly along the travel (a guide out of
//                                                 straightness, preload or lubrication varying along the rail)
//                                                 {center x₀, half_range h [m], slip_velocity v_s}: ξ^j,
//                                                 ξ = (x − x₀)/h, j = 1..3 (position_dependent_force's basis; j = 0
//                                                 is the base's level)
//   local_force_constant   ŷ × bump(x)            the force constant changes over one stretch (a chipped or
//                                                 demagnetised magnet) {center c, half_width w [m]}
//   force_constant_along_travel  ŷ × smooth(x)    the force constant changes along the travel (the air gap varying
//                                                 along the rail) {center x₀, half_range h [m]}
//   column_force_constant  ŷ × (c − c̄)            the force constant follows an unread column (a magnet temperature)
// (No slip(v) × column: on the oil-temperature case it stood in for the friction law's error at rest, which varies
// with the column over a stretch of the record, and was named before the viscous product that was the truth.)
// (|v| × periodic(x) is the catalogue's velocity_dependent_ripple.) Proposal: a smooth product over the record's travel
// when the axis travels both ways and no strong ripple is there to blur (RippleASmoothFunctionWouldBlur); a periodic
// product at the period of the residual demodulated by its multiplier (ModulatedPeriod: a friction along the pitch
// reverses with the direction of travel and cancels in the plain periodogram) and at every proposed position period; a
// local product at the place ScanBump finds, when it removes at least 0.5 % of the residual's sum of squares; v_s by
// BestSlipVelocity (the generator's friction along the pitch follows its tanh law: a sign with a 1.8 mm/s dead band
// left 1.4 × the noise floor, the error at the approach to rest and the dwell). The forward selection's held-out test
// on contiguous blocks decides; a column product is proposed for every unread column that is a new signal
// (UnreadColumnDuplicate). Blocks: a position_periodic ripple, a lookup_table_1d of the position, a
// position_dependent_force (the cubic) or a gain on an input connector reading the column, times the regularised sign
// of v, the velocity input or the model's force, through a product element summed into the force
// (tools/workflow/suggest.cc); a mass along the pitch is a position_dependent_inertia block on x, v and a.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"

namespace mb {
namespace {

constexpr double kMinBumpShare = 0.005;  // of the residual's sum of squares: a bump that removes less is noise
constexpr double kMinDirectionShare = 0.05;  // of the samples moving each way, for a product with sign(v)

// kSmooth: a cubic of the position over the travel; kColumn: an unread log column, not the position.
enum class PositionFactor { kPeriodic, kLocal, kSmooth, kColumn };
constexpr int kSmoothDegree = 3;  // ξ, ξ², ξ³: position_dependent_force's default

struct Product {
  const char* name;
  int catalogue_order;
  Multiplier multiplier;
  PositionFactor position;
  const char* physics;
  const char* formula;
};

const Product kProducts[] = {
    {"friction_ripple", 84, Multiplier::kSlip, PositionFactor::kPeriodic,
     "friction that varies with position along the pitch (magnetic attraction or preload changing along the pitch, a "
     "wavy guide): the direction of slip × a ripple of the position; add a ripple block whose output is multiplied by "
     "sign(v)",
     "tanh(v/v_s)·cos(2πkx/P), tanh(v/v_s)·sin(2πkx/P), k = 1..K"},
    {"force_constant_ripple", 85, Multiplier::kModelForce, PositionFactor::kPeriodic,
     "the force constant ripples with position (force/torque ripple of the motor): the force that acted × a ripple of "
     "the position; scale the motor's force constant by 1 + a ripple of the position",
     "ŷ·cos(2πkx/P), ŷ·sin(2πkx/P), k = 1..K, ŷ the model's force"},
    {"local_friction", 86, Multiplier::kSlip, PositionFactor::kLocal,
     "friction at one place of the travel (a damaged spot, a seal, debris, a tight stretch of the guide): the direction "
     "of slip × a bump over [c − w, c + w]; add a 1-D lookup table of the position multiplied by sign(v)",
     "tanh(v/v_s)·cos²(π(x − c)/(2w)) for |x − c| < w"},
    {"damping_ripple", 87, Multiplier::kVelocity, PositionFactor::kPeriodic,
     "the damping varies along the pitch (the back-EMF constant or the eddy currents of the magnet track ripple with "
     "position): v × a ripple of the position; add a ripple block whose output is multiplied by the velocity",
     "v·cos(2πkx/P), v·sin(2πkx/P), k = 1..K"},
    {"inertia_ripple", 88, Multiplier::kAcceleration, PositionFactor::kPeriodic,
     "the moving mass varies with position (an arm's inertia with its angle, a linkage or a cam whose lever changes "
     "along the travel): a mass M(x) periodic in the position acts as M(x)·a + ½M′(x)·v² (Lagrange's equation: the "
     "v² term is the kinetic energy the mass's change takes or gives back); add a position_dependent_inertia block",
     "a·cos(kθ) − ½(2πk/P)·v²·sin(kθ), a·sin(kθ) + ½(2πk/P)·v²·cos(kθ), θ = 2πx/P, k = 1..K"},
    {"local_damping", 89, Multiplier::kVelocity, PositionFactor::kLocal,
     "viscous drag at one place of the travel (a wiper or a seal, a stretch of thicker grease, a bellows): v × a bump "
     "over [c − w, c + w]; add a 1-D lookup table of the position multiplied by the velocity",
     "v·cos²(π(x − c)/(2w)) for |x − c| < w"},
    {"friction_along_travel", 90, Multiplier::kSlip, PositionFactor::kSmooth,
     "friction that changes smoothly along the travel (a guide out of straightness or parallelism, the preload or the "
     "lubrication varying along the rail, a cable carrier dragging more at one end): the direction of slip × a smooth "
     "function of the position; add a position_dependent_force block (a cubic of the position) multiplied by sign(v)",
     "tanh(v/v_s)·ξ^j, ξ = (x − x₀)/h, j = 1..3"},
    {"local_force_constant", 91, Multiplier::kModelForce, PositionFactor::kLocal,
     "the force constant changes over one stretch of the travel (a chipped, cracked or demagnetised magnet, a gap in "
     "the magnet track): the force that acted × a bump over [c − w, c + w]; add a 1-D lookup table of the position "
     "multiplied by the model's force",
     "ŷ·cos²(π(x − c)/(2w)) for |x − c| < w, ŷ the model's force"},
    {"force_constant_along_travel", 92, Multiplier::kModelForce, PositionFactor::kSmooth,
     "the force constant changes smoothly along the travel (the magnet track not parallel to the guide, so the air gap "
     "and the flux vary along the rail; magnets of another grade or temperature at one end): the force that acted × a "
     "smooth function of the position; add a position_dependent_force block (a cubic of the position) multiplied by "
     "the model's force",
     "ŷ·ξ^j, ξ = (x − x₀)/h, j = 1..3, ŷ the model's force"},
    {"column_damping", 123, Multiplier::kVelocity, PositionFactor::kColumn,
     "the viscous friction follows a column of the log that the diagram does not read (the lubricant's temperature: "
     "its viscosity): v × the column; add an input connector reading it, a gain, multiplied by the velocity",
     "v·(c − c̄), c a log column the diagram does not read"},
    {"column_force_constant", 124, Multiplier::kModelForce, PositionFactor::kColumn,
     "the force constant follows a column of the log that the diagram does not read (the magnets' or the coil's "
     "temperature: a neodymium magnet's flux falls by about 0.1 % per K): the force that acted × the column; add an "
     "input connector reading it, a gain, multiplied by the model's force",
     "ŷ·(c − c̄), c a log column the diagram does not read, ŷ the model's force"},
};

// The multiplier's slip velocity: the effect's parameter when the multiplier is the direction of slip, else unused.
double SlipVelocity(const Product& p, const EffectInstance& e) {
  return p.multiplier == Multiplier::kSlip ? PositiveParameter(e, "slip_velocity") : 0.0;
}

// The product's columns for the multiplier column m (N × K·2, N × kSmoothDegree or N × 1).
Eigen::MatrixXd Columns(const Product& p, const std::map<std::string, double>& parameters, const Eigen::VectorXd& m,
                        const DiagnosisSignals& s) {
  if (p.position == PositionFactor::kSmooth) {
    return PowerColumns(s.position, parameters.at("center"), parameters.at("half_range"), kSmoothDegree, p.name, &m)
        .columns;
  }
  if (p.position == PositionFactor::kLocal) {
    return m.cwiseProduct(Bump(s.position, parameters.at("center"), parameters.at("half_width")));
  }
  if (p.position == PositionFactor::kColumn) {
    return m.cwiseProduct(Centered(s.extra_columns.at(static_cast<std::size_t>(parameters.at("column")))));
  }
  return PeriodicColumns(s.position, parameters.at("period"), std::max(1, static_cast<int>(parameters.at("harmonics"))),
                         p.name, &m)
      .columns;
}

// Proposes the product with `parameters`, its slip velocity (BestSlipVelocity) when it multiplies the direction of
// slip.
void ProposeWith(const Product& p, ProposalContext& c, std::map<std::string, double> parameters) {
  if (p.multiplier == Multiplier::kSlip) {
    parameters["slip_velocity"] = BestSlipVelocity(
        c, [&](const Eigen::VectorXd& slip) { return Columns(p, parameters, slip, c.signals()); });
  }
  c.Propose(p.name, parameters);
}

EffectRegressors Regressors(const Product& p, const EffectInstance& e, const DiagnosisSignals& s) {
  // A factor of the position times the acceleration is a mass M(x): it acts as Lagrange's M(x)·a + ½M′(x)·v², never
  // as the plain product (a generator of a position-dependent mass carries the v² term, often the larger one).
  if (p.multiplier == Multiplier::kAcceleration) {
    return InertiaColumns(s.position, s.velocity, s.acceleration, PositiveParameter(e, "period"), HarmonicsParameter(e),
                          e.name);
  }
  const Eigen::VectorXd m = MultiplierColumn(p.multiplier, s, SlipVelocity(p, e), e.name);
  if (p.position == PositionFactor::kPeriodic) {
    return PeriodicColumns(s.position, PositiveParameter(e, "period"), HarmonicsParameter(e), e.name, &m);
  }
  if (p.position == PositionFactor::kColumn) return SingleColumn(e.name, m.cwiseProduct(Centered(UnreadColumn(e, s))));
  if (p.position == PositionFactor::kSmooth) {
    return PowerColumns(s.position, RequiredParameter(e, "center"), PositiveParameter(e, "half_range"), kSmoothDegree,
                        e.name, &m);
  }
  return SingleColumn(e.name,
                      m.cwiseProduct(Bump(s.position, RequiredParameter(e, "center"), PositiveParameter(e, "half_width"))));
}

void Propose(const Product& p, ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  if (!(c.max_speed() > 0.0)) return;
  // ŷ is the force only in equation-error mode (the logged command compared); in simulation mode it is the output.
  if (p.multiplier == Multiplier::kModelForce && (s.logged_command.size() != c.size() || s.model_output.size() != c.size())) {
    return;
  }
  // The place and the period are found with sign(v) outside the dead band as the direction of slip; the slip velocity
  // after (ProposeWith).
  const Eigen::VectorXd m = p.multiplier == Multiplier::kSlip ? SignDeadBand(s.velocity, c.dead_band())
                                                              : MultiplierColumn(p.multiplier, s, 0.0, p.name);
  // sign(v) × f is a friction only when the axis travels both ways: one way, it is f itself (position_periodic,
  // position_dependent_force, logged_column), which the catalogue proposes already; and v × f is |v| × f
  // (velocity_dependent_ripple).
  if (p.multiplier == Multiplier::kSlip || p.multiplier == Multiplier::kVelocity) {
    const Eigen::VectorXd direction = SignDeadBand(s.velocity, c.dead_band());
    const double n = static_cast<double>(c.size());
    const auto forward = static_cast<double>((direction.array() > 0.0).count());
    const auto back = static_cast<double>((direction.array() < 0.0).count());
    if (!(forward >= kMinDirectionShare * n && back >= kMinDirectionShare * n)) {
      return;
    }
  }
  if (p.position == PositionFactor::kColumn) {
    for (std::size_t k = 0; k < s.extra_columns.size(); ++k) {
      // A column that varies and is a new signal (logged_column notes the others).
      if (!(s.extra_columns[k].maxCoeff() > s.extra_columns[k].minCoeff()) || UnreadColumnDuplicate(s, k)) continue;
      ProposeWith(p, c, {{"column", static_cast<double>(k)}});
    }
    return;
  }
  if (p.position == PositionFactor::kSmooth) {
    const Eigen::VectorXd& x = s.position;
    if (!(c.position_span() > 0.0) || RippleASmoothFunctionWouldBlur(c)) return;
    ProposeWith(p, c, {{"center", 0.5 * (x.maxCoeff() + x.minCoeff())}, {"half_range", 0.5 * c.position_span()}});
    return;
  }
  if (p.position == PositionFactor::kLocal) {
    const BumpPlace place = ScanBump(c, m);
    if (!(place.explained >= kMinBumpShare)) return;
    ProposeWith(p, c, {{"center", place.center}, {"half_width", place.half_width}});
    return;
  }
  std::vector<ProposedPeriod> periods = c.position_periods();
  if (p.multiplier != Multiplier::kOne) {
    if (const std::optional<ProposedPeriod> own = ModulatedPeriod(c, m)) periods.insert(periods.begin(), *own);
  }
  std::vector<double> proposed;
  for (const ProposedPeriod& period : periods) {
    bool repeated = false;
    for (double q : proposed) repeated = repeated || std::abs(q - period.period) < 1e-3 * q;
    if (repeated) continue;
    proposed.push_back(period.period);
    ProposeWith(p, c, {{"period", period.period}, {"harmonics", period.harmonics}});
  }
}

EffectType ProductEffect(const Product& p) {
  EffectType t;
  t.name = p.name;
  t.catalogue_order = p.catalogue_order;
  t.physics = p.physics;
  t.regressor_formula = p.formula;
  if (p.position == PositionFactor::kPeriodic) {
    t.parameters = {{"period", "m", "P: the pitch"}, {"harmonics", "", "K, 1 when absent"}};
    t.traits.periodicity = Periodicity::kPosition;
    RefinePositionPeriod(&t.traits);  // the periodogram's peak placed by the joint fit
  } else if (p.position == PositionFactor::kLocal) {
    t.parameters = {{"center", "m", "c: the middle of the stretch where it acts"},
                    {"half_width", "m", "w: it acts over [c − w, c + w]"}};
  } else if (p.position == PositionFactor::kSmooth) {
    t.parameters = {{"center", "m", "x₀: the middle of the record's travel"},
                    {"half_range", "m", "h: half the record's travel"}};
  } else {
    t.parameters = {{"column", "", "the column's index among the log's unread columns (named in the description)"}};
  }
  if (p.multiplier == Multiplier::kSlip) {
    t.parameters.push_back({"slip_velocity", "m/s", "v_s: the direction of slip is tanh(v/v_s)"});
  }
  t.regressors = [&p](const EffectInstance& e, const DiagnosisSignals& s) { return Regressors(p, e, s); };
  t.propose = [&p](ProposalContext& c) { Propose(p, c); };
  return t;
}

bool RegisterProducts() {
  for (const Product& p : kProducts) EffectRegistry::Global().Add(ProductEffect(p));
  return true;
}

[[maybe_unused]] const bool kProductsRegistered = RegisterProducts();

}  // namespace
}  // namespace mb
