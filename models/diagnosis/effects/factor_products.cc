// The products of the diagnosis grammar (issue 45; factors.h): every row of the multipliers' table (what the force is
// proportional to: 1, slip, v, |v|, v·|v|, a, ŷ, ŷ·|ŷ|, |ŷ|·slip) crossed with every row of the modulators' table (what
// it varies with: 1, periodic, local or smooth in the position, an unread log column or its rate, a ramp, a step, a
// window, a warm-up or a vibration in time) is a candidate effect. No pair is written here and none is left out here: a
// pair that a hand-written effect of the catalogue holds (position_periodic is 1 × periodic(x), mass_change
// a × step(t), …) is that effect (EffectRegistry::Add); a pair that the base's columns reproduce (ŷ × 1) is the base
// itself and a multiplier constant over the record (|v| at one speed) makes the modulator's own pair: neither is
// proposed, each with a note.
//
// A pair's name comes from its rows (the modulator's pattern with the multiplier's noun: "damping_step",
// "inertia_window", "column_coulomb"); the names the catalogue gave the first products stay as they were (kAliases),
// so that diagrams and reports made before keep their meaning. Its words, its parameters, its regressors and its
// proposal come from the rows too:
//   regressors  the multiplier's column times the modulator's shape; a mass times a factor of the position acts as
//               M(x)·a + ½M′(x)·v² (Lagrange: the ½M′(x)·v² is the kinetic energy the mass's change takes or gives);
//               a multiplier the base has no parameter for also carries its own level (MultiplierRow::own_level).
//   proposal    the modulator's shape scan on the residual demodulated by the multiplier (a period, a bump, a break
//               time is found on what that multiplier leaves), for a multiplier of the direction of slip with sign(v)
//               outside the dead band, then its slip velocity v_s by BestSlipVelocity. A multiplier that reverses with
//               v needs the axis to travel both ways (one way, it is its even twin); one of ŷ needs equation-error
//               mode (in simulation mode ŷ is the compared motion).
// The forward selection's held-out test on contiguous blocks decides among them.
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/QR>
#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/loop_response.h"

namespace mb {
namespace {

constexpr double kMinDirectionShare = 0.05;  // of the samples moving each way, for a multiplier that reverses with v
// A multiplier whose column varies by less than this share of its mean square over the record is a constant there: its
// pairs are the modulators' own (1 × the modulator), identical candidates (|v| × periodic(t) at one speed).
constexpr double kConstantMultiplier = 1e-2;
// A pair whose every column the base's columns reproduce to this share of its sum of squares is the base model itself
// (ŷ × 1 scales every base parameter at once): not a candidate. Checked when it is proposed, before a friction-law
// replacement changes the base's law and leaves ŷ carrying the old one back in.
constexpr double kInTheBase = 0.999;

// A multiplier's column that the base reproduces to this share is the base's (DiagnosisOptions::redundant_with_base):
// its pairs carry no level of their own (MultiplierRow::own_level) — a column that is the base's but for its last
// percent fits whatever that percent holds (|ŷ|·sign(v) is 99.8 % a Coulomb level where friction dominates ŷ, and its
// rest is ŷ's own ripple: a vibration of the Coulomb level was named a load friction drifting).
constexpr double kLevelInTheBase = 0.98;

// Whether the base's columns (with a constant) reproduce every one of `columns` to `share` of its sum of squares.
bool IsTheBase(const ProposalContext& c, const Eigen::MatrixXd& columns, double share = kInTheBase) {
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(base);
  for (Eigen::Index j = 0; j < columns.cols(); ++j) {
    const double total = columns.col(j).squaredNorm();
    if (!(total > 0.0)) continue;
    const Eigen::VectorXd left = columns.col(j) - base * qr.solve(columns.col(j));
    if (left.squaredNorm() > (1.0 - share) * total) return false;
  }
  return true;
}

// The names the catalogue gave its first products, and their place in it (EffectType::catalogue_order): kept.
struct Alias {
  const char* multiplier;
  const char* modulator;
  const char* name;
  int catalogue_order;
};
constexpr Alias kAliases[] = {
    {"slip", "position_periodic", "friction_ripple", 84},
    {"model_force", "position_periodic", "force_constant_ripple", 85},
    {"slip", "position_local", "local_friction", 86},
    {"velocity", "position_periodic", "damping_ripple", 87},
    {"acceleration", "position_periodic", "inertia_ripple", 88},
    {"velocity", "position_local", "local_damping", 89},
    {"slip", "position_smooth", "friction_along_travel", 90},
    {"model_force", "position_local", "local_force_constant", 91},
    {"model_force", "position_smooth", "force_constant_along_travel", 92},
    {"velocity", "column", "column_damping", 123},
    {"model_force", "column", "column_force_constant", 124},
};
constexpr int kFirstGeneratedOrder = 200;  // generated pairs come after the catalogue's effects, in table order

struct Pair {
  const MultiplierRow* multiplier;
  const ModulatorRow* modulator;
  std::string name;
  bool named_before = false;  ///< one of kAliases: proposed even without CatalogueOptions::every_pair
};

// Whether the pair may carry its multiplier's constant part as a column of its own (MultiplierRow::own_level): for a
// modulator with a mean, not for a periodic one (zero mean over its cycles) nor for the constant (it is the level).
// Each proposal says whether it does (its parameter "own_level": not where the base reproduces the multiplier).
bool HasOwnLevel(const Pair& p) {
  return p.multiplier->own_level && p.modulator->periodicity == Periodicity::kNone &&
         p.modulator->id != std::string_view("constant");
}

bool CarriesLevel(const Pair& p, const FactorParameters& parameters) {
  const auto it = parameters.find("own_level");
  return HasOwnLevel(p) && it != parameters.end() && it->second == 1.0;
}

// The pair's columns on the signals with the direction of slip `slip` (N; unused unless the multiplier holds it).
EffectRegressors Columns(const Pair& p, const FactorParameters& parameters, const DiagnosisSignals& s,
                         const Eigen::VectorXd& slip) {
  if (p.multiplier->lagrange && p.modulator->of_position) {
    EffectRegressors r = p.modulator->shape(parameters, s, p.name, &s.acceleration);
    r.columns += p.modulator->shape_derivative(parameters, s, (0.5 * s.velocity.array().square()).matrix());
    return r;
  }
  const Eigen::VectorXd m = p.multiplier->column(s, slip, p.name);
  EffectRegressors r = p.modulator->shape(parameters, s, p.name, &m);
  if (CarriesLevel(p, parameters)) {
    r.columns.conservativeResize(Eigen::NoChange, r.columns.cols() + 1);
    r.columns.rightCols(1) = m;
    r.column_names.push_back(p.name + ".level");
  }
  return r;
}

bool TravelsBothWays(const ProposalContext& c) {
  const Eigen::VectorXd direction = SignDeadBand(c.signals().velocity, c.dead_band());
  const double n = static_cast<double>(c.size());
  return static_cast<double>((direction.array() > 0.0).count()) >= kMinDirectionShare * n &&
         static_cast<double>((direction.array() < 0.0).count()) >= kMinDirectionShare * n;
}

void Propose(const Pair& p, ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  if (!(c.max_speed() > 0.0) || !(p.named_before || c.options().every_pair)) return;
  // ŷ is the model output only in equation-error mode (the logged command compared); in simulation mode the output is
  // the position, and ŷ is the simulated drive force when the comparison found one.
  const bool drive_force = s.drive_force.size() == c.size() ||
                           (s.logged_command.size() == c.size() && s.model_output.size() == c.size());
  if (p.multiplier->model_force && !drive_force) return;
  if (p.multiplier->odd_in_velocity && !TravelsBothWays(c)) return;
  // The shape is found with sign(v) outside the dead band as the direction of slip; the slip velocity after.
  const Eigen::VectorXd sign = SignDeadBand(s.velocity, c.dead_band());
  const Eigen::VectorXd m = p.multiplier->column(s, sign, p.name);
  if (p.multiplier->id != std::string_view("one")) {
    const double mean_square = m.squaredNorm() / static_cast<double>(m.size());
    const double variance = (m.array() - m.mean()).square().mean();
    if (!(variance > kConstantMultiplier * mean_square)) {
      c.Note(fmt::format("{} ({}) is nearly constant over the record: its products are the modulators' own, not proposed "
                         "again",
                         p.multiplier->phrase, p.multiplier->formula));
      return;
    }
  }
  // A pair with its own level is scanned beside it: the break, the bump or the warm-up is found on what the level
  // (the multiplier's constant part, at the loop's output in simulation mode) leaves.
  const bool level = HasOwnLevel(p) && !IsTheBase(c, m, kLevelInTheBase);
  Eigen::MatrixXd with_level;
  if (level) {
    with_level.resize(c.size(), c.base_columns().cols() + 1);
    with_level << c.base_columns(), c.loop() != nullptr ? c.loop()->Apply(m).col(0).eval() : m;
  }
  ProposalContext scan_context = level ? c.WithBase(with_level) : c;
  Eigen::VectorXd kinetic;  // a mass times a factor of the position: ½v² times the factor's slope (Lagrange)
  if (p.multiplier->lagrange && p.modulator->of_position) kinetic = 0.5 * s.velocity.array().square().matrix();
  for (FactorParameters parameters :
       p.modulator->scan(scan_context, m, kinetic.size() > 0 ? &kinetic : nullptr, p.name)) {
    if (HasOwnLevel(p)) parameters["own_level"] = level ? 1.0 : 0.0;
    if (p.multiplier->slip) {
      parameters["slip_velocity"] = BestSlipVelocity(
          c, [&](const Eigen::VectorXd& slip) { return Columns(p, parameters, s, slip).columns; });
    }
    const EffectRegressors columns = Columns(p, parameters, s, sign);
    if (p.modulator->periodicity == Periodicity::kNone && IsTheBase(c, columns.columns)) {
      c.Note(fmt::format("{} is the base model itself ({} × {}: the base's parameters reproduce it): not proposed",
                         p.name, p.multiplier->formula, p.modulator->formula));
      continue;
    }
    c.Propose(p.name, std::move(parameters));
  }
}

EffectType PairEffect(const Pair& p, int catalogue_order) {
  const MultiplierRow& m = *p.multiplier;
  const ModulatorRow& mod = *p.modulator;
  EffectType t;
  t.name = p.name;
  t.catalogue_order = catalogue_order;
  t.multiplier = m.id;
  t.modulator = mod.id;
  t.generated = true;
  t.searched = !p.named_before;
  t.physics = *mod.phrase == '\0' ? fmt::format("{} ({})", m.phrase, m.physics)
                                  : fmt::format("{} {} ({}; {})", m.phrase, mod.phrase, m.physics, mod.physics);
  t.regressor_formula = fmt::format("{} × {}", m.formula, mod.formula);
  t.parameters = mod.parameters;
  if (m.slip) t.parameters.push_back({"slip_velocity", "m/s", "v_s: the direction of slip is tanh(v/v_s)"});
  if (HasOwnLevel(p)) {
    t.parameters.push_back({"own_level", "",
                            "1 when the pair carries its multiplier's constant part as a column of its own (the "
                            "base has none), 0 when the base's refit takes it"});
  }
  t.traits.periodicity = mod.periodicity;
  t.traits.nests_constant_pair = HasOwnLevel(p);
  t.traits.nested_modulators = mod.nests;
  if (mod.refine) mod.refine(&t.traits);
  t.regressors = [p](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd slip = p.multiplier->slip
                                     ? (s.velocity.array() / PositiveParameter(e, "slip_velocity")).tanh().matrix().eval()
                                     : Eigen::VectorXd();
    return Columns(p, e.parameters, s, slip);
  };
  t.propose = [p](ProposalContext& c) { Propose(p, c); };
  return t;
}

bool RegisterProducts() {
  int order = kFirstGeneratedOrder;
  for (const MultiplierRow& m : Multipliers()) {
    for (const ModulatorRow& mod : Modulators()) {
      Pair pair{&m, &mod, PairName(m, mod)};
      int pair_order = order++;
      for (const Alias& a : kAliases) {
        if (m.id == std::string_view(a.multiplier) && mod.id == std::string_view(a.modulator)) {
          pair.name = a.name;
          pair.named_before = true;
          pair_order = a.catalogue_order;
        }
      }
      EffectRegistry::Global().Add(PairEffect(pair, pair_order));
    }
  }
  return true;
}

[[maybe_unused]] const bool kProductsRegistered = RegisterProducts();

}  // namespace
}  // namespace mb
