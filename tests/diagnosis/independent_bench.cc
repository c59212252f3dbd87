#include "tests/diagnosis/independent_bench.h"

#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/signal_processing.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement.h"

namespace mb::independent {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kEmps = fs::path(MB_SOURCE_DIR) / "diagrams" / "emps";

// The user's diagram: the EMPS rigid body as shipped (M, Fv, Fc, offset free; sign(v) friction); with the mass
// known, 94 kg fixed.
json UserDiagram(bool mass_known) {
  json d = ReadDiagramJson(kEmps / "rigid_body.json");
  if (mass_known) {
    d["free"] = {"friction.viscous", "friction.coulomb", "offset.value"};
    SetParameterValues(&d, ResolveFreeParameters(d, {"inertia.gain"}), Eigen::VectorXd::Constant(1, 94.0));
  }
  return d;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// A friction-law replacement (a new law near zero velocity, not a missing effect). Main's catalogue has none yet:
// every named effect counts.
bool IsLaw(const std::string& /*effect*/) { return false; }

// The truth's force on the record as compare reads it (derived motion, parallel filtering) against the measured.
double NoiseFloor(Hidden hidden, const MeasurementLog& log, const MeasurementSettings& settings) {
  const Eigen::VectorXd truth = TruthForce(hidden, log.time(), log.column("position_m"),
                                           log.column(kDerivedVelocityColumn), log.column(kDerivedAccelerationColumn));
  const Eigen::VectorXd filtered = ZeroPhaseLowPass(truth, MedianTimeStep(log.time()), settings.derivative_cutoff_hz);
  return Rmse(log.column("force_N"), filtered);
}

void Judge(const DiagnosisResult& d, CaseResult* r) {
  r->parameter = std::numeric_limits<double>::quiet_NaN();
  bool second = r->spec.second_effect.empty();
  bool law_named = false;
  for (const auto& e : d.effects) {
    const bool law = IsLaw(e.effect);
    r->named.push_back(e.effect + (law ? " (law)" : ""));
    second = second || e.effect == r->spec.second_effect;
    const bool key = r->spec.law ? e.effect == r->spec.effect : !law && r->named_first.empty();
    if (!law && r->named_first.empty()) r->named_first = e.effect;
    if (!key) continue;
    law_named = law_named || r->spec.law;
    const auto it = e.parameters.find(r->spec.parameter);
    if (it != e.parameters.end()) r->parameter = it->second;
  }
  // Two effects at once: both must be named outside the law (in either order); the key parameter is the first's.
  bool first = r->named_first == r->spec.effect;
  if (!r->spec.second_effect.empty()) {
    first = false;
    for (const auto& e : d.effects) {
      if (e.effect != r->spec.effect) continue;
      first = true;
      const auto it = e.parameters.find(r->spec.parameter);
      if (it != e.parameters.end()) r->parameter = it->second;
    }
  }
  r->named_right = r->spec.law ? law_named && r->named_first.empty() : first && second;
  r->parameter_right = r->spec.parameter.empty()
                           ? r->named_right
                           : std::abs(r->parameter - r->spec.truth) <= r->spec.tolerance * std::abs(r->spec.truth);
}

}  // namespace

CaseResult RunCase(const CaseSpec& spec, const fs::path& directory, bool run_improve, double jitter) {
  CaseResult r;
  r.spec = spec;
  fs::create_directories(directory);
  const fs::path train = directory / "training.csv", valid = directory / "validation.csv";
  WriteCsv(Generate(spec.hidden, {.jitter = jitter, .seed = 11}), train.string());
  WriteCsv(Generate(spec.hidden, {.jitter = jitter, .seed = 23}), valid.string());
  const json diagram = UserDiagram(spec.mass_known);
  ImproveSettings settings;
  const auto t0 = std::chrono::steady_clock::now();
  const MeasurementLog training = ReadMeasurementFor(diagram, train.string(), settings.measurement);
  const DiagnosedComparison compared = CompareAndDiagnose(diagram, kEmps, "rigid_body.json", training,
                                                          settings.measurement, diagram["free"]);
  r.compare_seconds = Seconds(t0);
  Judge(*compared.diagnosis, &r);
  const MeasurementLog validation = ReadMeasurementFor(diagram, valid.string(), settings.measurement);
  r.noise_floor = NoiseFloor(spec.hidden, validation, settings.measurement);
  if (!run_improve) return r;
  r.improve_run = true;
  const auto t1 = std::chrono::steady_clock::now();
  const ImproveResult improved = ImproveModel(diagram, kEmps, "rigid_body.json", training, &validation, settings);
  r.improve_seconds = Seconds(t1);
  r.heldout_before = improved.first().rmse_heldout;
  r.heldout_after = improved.last_accepted().rmse_heldout;
  r.floor_reached = r.heldout_after <= 1.3 * r.noise_floor;
  return r;
}

namespace {

// "yes", or what failed; without improve, the naming and the parameter only.
std::string Verdict(const CaseResult& r) {
  const bool compared = r.named_right && r.parameter_right;
  if (!r.improve_run) {
    return compared ? "named, parameter right (improve not run)"
                    : fmt::format("no ({}{})", r.named_right ? "" : "name ", r.parameter_right ? "" : "parameter");
  }
  if (r.pass()) return "yes";
  return fmt::format("no ({}{}{})", r.named_right ? "" : "name ", r.parameter_right ? "" : "parameter ",
                     r.floor_reached ? "" : "floor");
}

}  // namespace

std::string FormatTable(const std::vector<CaseResult>& results) {
  std::string out =
      "| case | named (ranking; (law) = friction-law replacement) | first outside the law | key parameter found "
      "(truth) | held-out RMSE before → after improve (noise floor) [N] | compare / improve [s] | pass |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    std::string named;
    for (const auto& n : r.named) named += (named.empty() ? "" : ", ") + n;
    std::string parameter = "—";
    if (!r.spec.parameter.empty()) {
      parameter = fmt::format("{} {:.4g} ({:.4g})", r.spec.parameter, r.parameter, r.spec.truth);
    }
    const std::string heldout =
        r.improve_run ? fmt::format("{:.3f} → {:.3f} ({:.3f})", r.heldout_before, r.heldout_after, r.noise_floor)
                      : fmt::format("not run ({:.3f})", r.noise_floor);
    const std::string seconds = r.improve_run ? fmt::format("{:.2f} / {:.1f}", r.compare_seconds, r.improve_seconds)
                                              : fmt::format("{:.2f} / —", r.compare_seconds);
    out += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", r.spec.name,
                       named.empty() ? "nothing" : named, r.named_first.empty() ? "—" : r.named_first, parameter,
                       heldout, seconds,
                       Verdict(r));
  }
  return out;
}

}  // namespace mb::independent
