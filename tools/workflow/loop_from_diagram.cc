#include "tools/workflow/loop_from_diagram.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/block_roles.h"

namespace mb {

namespace {

// The block types that can be a part of the loop: those declaring the role in their own file
// (MB_REGISTER_LOOP_ROLES, engine/block_roles.h).
std::vector<std::string> TypesFor(const std::string& role) {
  return BlockRoleRegistry::Global().TypesWithLoopRole(role);
}

std::string Join(const std::vector<std::string>& items, const char* separator) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : separator) + item;
  return out;
}

// The loop's parts of one diagram, looked up by role or type.
class LoopFinder {
 public:
  explicit LoopFinder(const Diagram& diagram) : d_(diagram) {}

  /// The block in `role`: the "roles" entry (checked against the types that can be it), else the one block of
  /// those types; -1 if there is none and the part is optional. Blocks in `exclude` are not candidates.
  int Find(const std::string& role, bool required, const std::vector<int>& exclude = {}) const {
    const std::vector<std::string> types = TypesFor(role);
    if (const auto it = d_.roles().find(role); it != d_.roles().end()) {
      const int b = d_.FindBlock(it->second);
      if (std::find(types.begin(), types.end(), d_.block_type(b)) == types.end()) {
        throw std::invalid_argument(fmt::format("stability analysis: roles/{} names '{}', a {}; the {} must be a {}",
                                                role, it->second, d_.block_type(b), role, Join(types, " or ")));
      }
      return b;
    }
    std::vector<int> found;
    for (int b = 0; b < static_cast<int>(d_.blocks().size()); ++b) {
      if (std::find(exclude.begin(), exclude.end(), b) != exclude.end()) continue;
      if (std::find(types.begin(), types.end(), d_.block_type(b)) != types.end()) found.push_back(b);
    }
    if (found.size() > 1) {
      std::vector<std::string> names;
      for (int b : found) names.push_back(d_.blocks()[static_cast<std::size_t>(b)]->name());
      throw std::invalid_argument(fmt::format(
          "stability analysis: the diagram has {} elements that could be the {} ({}): name the one in the loop with "
          "\"roles\": {{\"{}\": \"{}\"}}",
          found.size(), role, Join(names, ", "), role, names.front()));
    }
    if (found.empty() && required) {
      throw std::invalid_argument(fmt::format(
          "stability analysis: the diagram has no {} (an element of type {}); the analysis reads a closed loop: a "
          "plant, a PD and optionally a dob and the GP path (see diagrams/paper/conventional.json)",
          role, Join(types, " or ")));
    }
    return found.empty() ? -1 : found.front();
  }

  /// The block named by `role` in "roles" (-1 if the role is not given), checked to be of a type that can be it.
  int Role(const std::string& role) const { return d_.roles().count(role) ? Find(role, true) : -1; }

  const Parameters& Of(int b) const { return d_.block_parameters(b); }
  double Period(int b) const { return d_.blocks()[static_cast<std::size_t>(b)]->sample_time().period; }
  bool Discrete(int b) const { return d_.blocks()[static_cast<std::size_t>(b)]->sample_time().is_discrete(); }
  const std::string& Name(int b) const { return d_.blocks()[static_cast<std::size_t>(b)]->name(); }
  /// True if a block that can be `role` has string parameter `parameter` equal to `value`.
  bool HasRoleWith(const std::string& role, const std::string& parameter, const std::string& value) const {
    const std::vector<std::string> types = TypesFor(role);
    for (int b = 0; b < static_cast<int>(d_.blocks().size()); ++b) {
      if (std::find(types.begin(), types.end(), d_.block_type(b)) != types.end() &&
          Of(b).String(parameter) == value) {
        return true;
      }
    }
    return false;
  }
  const Diagram& diagram() const { return d_; }

 private:
  const Diagram& d_;
};

void ReadPlant(const LoopFinder& f, PaperLoop* l) {
  const int b = f.Find("plant", true);
  const Parameters& p = f.Of(b);
  l->mass = p.Number("mass") + (p.Has("payload_mass") ? p.Number("payload_mass") : 0.0);
  l->damping = p.Number("damping");
}

// The DOB, if any; its period becomes Ts.
void ReadDob(const LoopFinder& f, PaperLoop* l) {
  const int b = f.Find("dob", false);
  l->has_dob = b >= 0;
  if (b < 0) return;
  const Parameters& p = f.Of(b);
  l->nominal_mass = p.Number("nominal_mass");
  l->nominal_damping = p.Number("nominal_damping");
  l->q_cutoff_hz = p.Number("cutoff_hz");
  l->relative_degree = p.Integer("relative_degree");
  l->q_nominal_inverse_discretization = ParseDiscretization(p.String("discretization"), "dob/discretization");
  l->sample_time = f.Period(b);
}

// A discrete pd_controller: its derivative pole a as the velocity-estimator cut-off that gives the same a.
void ReadPdController(const LoopFinder& f, int b, PaperLoop* l) {
  if (!f.Discrete(b)) {
    throw std::invalid_argument(fmt::format("stability analysis: the PD '{}' is continuous; the analysis is of the "
                                            "sampled loop: give it a \"sampleTime\": [Ts, 0]",
                                            f.Name(b)));
  }
  const Parameters& p = f.Of(b);
  const double ts = f.Period(b), tf = p.Number("derivative_filter");
  const bool tustin = p.String("method") == "tustin";
  const double a = tustin ? (2.0 * tf - ts) / (2.0 * tf + ts) : tf / (tf + ts);
  if (!(a > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "stability analysis: the PD '{}' has derivative pole a = {:.4g} (T_f = {} s, Ts = {} s); the analysis models "
        "the derivative filter as a first-order low-pass with 0 < a < 1: use T_f > {} s",
        f.Name(b), a, tf, ts, tustin ? ts / 2.0 : 0.0));
  }
  l->kp = p.Number("kp");
  l->kd = p.Number("kd");
  l->derivative_cutoff_hz = -std::log(a) / (2.0 * std::numbers::pi * ts);
  if (!l->has_dob) l->sample_time = ts;
}

// The PD: a pd_controller, else gains and a velocity estimator named in "roles". Returns the blocks it uses.
std::vector<int> ReadPd(const LoopFinder& f, PaperLoop* l) {
  if (const int b = f.Find("pd", false); b >= 0) {
    ReadPdController(f, b, l);
    return {b};
  }
  const int p = f.Role("pd_proportional_gain");
  const int d = f.Role("pd_derivative_gain");
  const int filter = f.Role("pd_derivative_filter");
  if (p < 0 || d < 0 || filter < 0) {
    throw std::invalid_argument(fmt::format(
        "stability analysis: the diagram has no {}; for a PD built of blocks name its parts in \"roles\": "
        "pd_proportional_gain and pd_derivative_gain ({} elements), pd_derivative_filter (a {}), "
        "as diagrams/paper/conventional.json does",
        Join(TypesFor("pd"), " or "), Join(TypesFor("pd_proportional_gain"), " or "),
        Join(TypesFor("pd_derivative_filter"), " or ")));
  }
  l->kp = f.Of(p).Vector("gain")(0);
  l->kd = f.Of(d).Vector("gain")(0);
  l->derivative_cutoff_hz = f.Of(filter).Number("cutoff_hz");
  if (!l->has_dob) l->sample_time = f.Period(filter);
  return {p, d, filter};
}

void ReadGpPath(const LoopFinder& f, const std::vector<int>& pd_blocks, PaperLoop* l) {
  if (const int v = f.Find("gp_velocity_filter", false, pd_blocks); v >= 0) {
    l->velocity_cutoff_hz = f.Of(v).Number("cutoff_hz");
  }
  if (const int g = f.Find("gp_filter", false); g >= 0) {
    const Parameters& p = f.Of(g);
    l->gp_weight = p.Number("weight");
    l->gp_cutoff_hz = p.Number("cutoff_hz");
    l->gp_order = p.Integer("order");
  }
  if (const int m = f.Find("gp", false); m >= 0) {
    l->gp_confidence_weighting = f.Of(m).Bool("confidence_weighting");
  }
  if (const int a = f.Find("adaptive_feedforward", false); a >= 0) {
    l->has_adaptive_mass = true;
    l->adaptive_mass_min = f.Of(a).Number("min_mass");
    l->adaptive_mass_max = f.Of(a).Number("max_mass");
  }
}

}  // namespace

PaperLoop PaperLoopFromDiagram(const Diagram& diagram) {
  const LoopFinder finder(diagram);
  PaperLoop l;
  ReadPlant(finder, &l);
  ReadDob(finder, &l);
  const std::vector<int> pd_blocks = ReadPd(finder, &l);
  ReadGpPath(finder, pd_blocks, &l);
  l.has_feedforward = diagram.roles().count("feedforward") ? finder.Find("feedforward", true) >= 0
                                                           : finder.HasRoleWith("feedforward", "form", "derivatives");
  return l;
}

StabilityReport AnalyseStability(const Diagram& diagram, const GprModel* gpr, const StabilityOptions& options) {
  return AnalyseStability(PaperLoopFromDiagram(diagram), gpr, options);
}

}  // namespace mb
