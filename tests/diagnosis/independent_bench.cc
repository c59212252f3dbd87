#include "tests/diagnosis/independent_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/diagram_loader.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/signal_processing.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/equation_error_view.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement.h"

namespace mb::independent {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kEmps = fs::path(MB_SOURCE_DIR) / "diagrams" / "emps";

// The user's diagram: the EMPS rigid body as shipped (M, Fv, Fc, offset free; sign(v) friction); with the mass
// known, 94 kg fixed.
const fs::path kRotary = fs::path(MB_SOURCE_DIR) / "diagrams" / "rotary";

// The user's diagram's folder and file: the EMPS rigid body, or on a rotary case the rigid arm (rad, N·m).
fs::path DiagramFolder(const CaseSpec& spec) { return IsRotary(spec.hidden) ? kRotary : kEmps; }
const char* DiagramFile(const CaseSpec& spec) { return IsRotary(spec.hidden) ? "rigid_arm.json" : kUserDiagramFile; }

json UserDiagram(const CaseSpec& spec) {
  const bool mass_known = spec.mass_known;
  json d = ReadDiagramJson(DiagramFolder(spec) / DiagramFile(spec));
  if (mass_known) {
    d["free"] = {"friction.viscous", "friction.coulomb", "offset.value"};
    SetParameterValues(&d, ResolveFreeParameters(d, {"inertia.gain"}), Eigen::VectorXd::Constant(1, 94.0));
  }
  return d;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// A friction-law replacement (a new law near zero velocity, not a missing effect): the registry's trait.
bool IsLaw(const std::string& effect) { return LookupEffect(effect).traits.friction_law_replacement; }

// The truth's force on the record as compare reads it (derived motion, parallel filtering) against the measured.
double NoiseFloor(Hidden hidden, const MeasurementLog& log, const MeasurementSettings& settings) {
  const std::string& x = settings.position_column;
  const std::string force = IsRotary(hidden) ? "torque_Nm" : "force_N";
  const Eigen::VectorXd logged = log.column(force);
  const Eigen::VectorXd truth = TruthForce(hidden, log.time(), log.column(x), log.column(DerivedVelocityColumn(x)),
                                           log.column(DerivedAccelerationColumn(x)), &logged);
  const Eigen::VectorXd filtered =
      ZeroPhaseLowPass(truth, MedianTimeStep(log.time()), DerivativeCutoffHz(settings, log));
  return Rmse(logged, filtered);
}

// Named right: the hidden effect first outside the friction-law replacements; a law case (Stribeck): among the
// replacements, nothing named outside them; two effects: the first two outside the replacements, in either order.
// The key parameter is read from the hidden (first) effect's entry.
constexpr double kCleanNamedShare = 0.02;

void Judge(const DiagnosisResult& d, CaseResult* r) {
  r->parameter = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> outside;
  const DiagnosedEffect* key = nullptr;
  for (const auto& e : d.effects) {
    const bool law = IsLaw(e.effect);
    r->named.push_back(e.effect + (law ? " (law)" : ""));
    r->details.push_back(fmt::format("{}: score {:.4f}, {}; coefficients {:.4g}", e.effect, e.score,
                                     fmt::join(e.parameters, ", "),
                                     fmt::join(e.coefficients.data(), e.coefficients.data() + e.coefficients.size(), ", ")));
    // On a clean record, what explains less than 2 % of the held-out residual is not counted as named (issue 46).
    if (!law && (!r->spec.effect.empty() || e.score >= kCleanNamedShare)) outside.push_back(e.effect);
    if (key == nullptr && e.effect == r->spec.effect) key = &e;
  }
  for (const auto& c : d.candidates) {
    if (!c.parameters.empty()) r->details.push_back(fmt::format("candidate {}: {}", c.name, fmt::join(c.parameters, ", ")));
  }
  r->details.insert(r->details.end(), d.notes.begin(), d.notes.end());
  if (!outside.empty()) r->named_first = outside.front();
  if (r->spec.law) {
    r->named_right = key != nullptr && outside.empty();
  } else if (!r->spec.second_effect.empty()) {
    const std::vector<std::string> pair{r->spec.effect, r->spec.second_effect};
    r->named_right = outside.size() >= 2 && std::is_permutation(outside.begin(), outside.begin() + 2, pair.begin());
  } else {
    r->named_right = r->named_first == r->spec.effect;
  }
  if (key != nullptr) {
    r->parameters = key->parameters;
    const auto it = key->parameters.find(r->spec.parameter);
    if (it != key->parameters.end()) r->parameter = it->second;
  }
  r->parameter_right = r->spec.parameter.empty()
                           ? r->named_right
                           : std::abs(r->parameter - r->spec.truth) <= r->spec.tolerance * std::abs(r->spec.truth);
}

}  // namespace

fs::path UserDiagramDirectory() { return kEmps; }

PreparedCase PrepareCase(const CaseSpec& spec, const fs::path& directory, double jitter, double duration) {
  fs::create_directories(directory);
  const fs::path train = directory / "training.csv", valid = directory / "validation.csv";
  for (const auto& [path, seed] : {std::pair{train, 11U}, std::pair{valid, 23U}}) {
    WriteCsv(Generate(spec.hidden, {.duration = duration,
                                    .sample_period = spec.sample_period,
                                    .jitter = jitter,
                                    .stamp_noise = spec.stamp_noise,
                                    .seed = seed}),
             path.string());
  }
  const json diagram = UserDiagram(spec);
  ImproveSettings settings;
  if (IsRotary(spec.hidden)) settings.measurement.position_column = "angle_rad";
  // The generator logs the controller's force command, held by the amplifier until the next sample (--intersample zoh);
  // a log slower than the controller samples the command (foh).
  if (spec.sample_period <= 1e-3) settings.measurement.intersample = Intersample::kZeroOrderHold;
  return {diagram, settings, ReadMeasurementFor(diagram, train.string(), settings.measurement),
          ReadMeasurementFor(diagram, valid.string(), settings.measurement)};
}

CaseResult RunCase(const CaseSpec& spec, const fs::path& directory, bool run_improve, double jitter) {
  CaseResult r;
  r.spec = spec;
  const PreparedCase prepared = PrepareCase(spec, directory, jitter);
  const json& diagram = prepared.diagram;
  const ImproveSettings& settings = prepared.settings;
  const auto t0 = std::chrono::steady_clock::now();
  const DiagnosedComparison compared = CompareAndDiagnose(diagram, DiagramFolder(spec), DiagramFile(spec),
                                                          prepared.training,
                                                          settings.measurement, diagram["free"]);
  r.compare_seconds = Seconds(t0);
  Judge(*compared.diagnosis, &r);
  const MeasurementLog& training = prepared.training;
  const MeasurementLog& validation = prepared.validation;
  r.noise_floor = NoiseFloor(spec.hidden, validation, settings.measurement);
  if (!run_improve) return r;
  r.improve_run = true;
  const auto t1 = std::chrono::steady_clock::now();
  const ImproveResult improved =
      ImproveModel(DiagramDocument(diagram, DiagramFolder(spec), DiagramFile(spec)), training, &validation, settings);
  r.improve_seconds = Seconds(t1);
  r.heldout_before = improved.first().rmse_heldout;
  r.heldout_after = improved.last_accepted().rmse_heldout;
  r.floor_reached = r.heldout_after <= 1.3 * r.noise_floor && r.heldout_after >= 0.7 * r.noise_floor;
  return r;
}

std::optional<CaseResult> RunCaseInSimulation(const CaseSpec& given, const fs::path& directory, unsigned seed,
                                              bool run_improve) {
  if (IsRotary(given.hidden)) return std::nullopt;
  CaseSpec spec = given;
  if (OnlyInTheLoggedForce(spec.hidden)) {
    spec.effect.clear();
    spec.parameter.clear();
  }
  if (spec.hidden == Hidden::kRippleAndDelay) spec.second_effect.clear();  // the delay is the logged force's
  CaseResult r;
  r.spec = spec;
  fs::create_directories(directory);
  const auto write = [&](Hidden hidden, unsigned record_seed, const std::string& name) {
    const fs::path path = directory / name;
    WriteCsv(Generate(hidden, {.duration = 16.0,
                               .sample_period = spec.sample_period,
                               .stamp_noise = spec.stamp_noise,
                               .seed = record_seed,
                               .log_reference = true}),
             path.string());
    return path;
  };
  const fs::path train = write(spec.hidden, seed, "training.csv");
  const fs::path folder = fs::path(MB_SOURCE_DIR) / "tests" / "diagnosis" / "data";
  const char* file = "independent_closed_loop.json";
  json diagram = ReadDiagramJson(folder / file);
  // The user models the controller at the rate it runs: the diagram's 1 kHz, or the log's own above it.
  const double control_period = ControlPeriod(spec.sample_period);
  for (json& element : diagram["elements"]) {
    if (element.contains("sampleTime")) element["sampleTime"][0] = control_period;
    if (element["type"] == "velocity_estimator") {
      element["parameters"]["cutoff_hz"] = VelocityEstimateCutoffHz(control_period);
    }
  }
  if (spec.mass_known) diagram["free"] = {"friction.viscous", "friction.coulomb", "offset.value"};
  MeasurementSettings settings;
  const MeasurementLog log = ReadMeasurementFor(diagram, train.string(), settings);
  const auto t0 = std::chrono::steady_clock::now();
  const DiagnosedComparison compared = CompareAndDiagnose(diagram, folder, file, log, settings, diagram["free"]);
  r.compare_seconds = Seconds(t0);
  Judge(*compared.diagnosis, &r);
  const auto t_view = std::chrono::steady_clock::now();
  const EquationErrorView view = DiagnoseEquationErrorView(compared, folder, file, log, settings);
  r.equation_error_seconds = Seconds(t_view);
  r.equation_error_run = true;
  r.equation_error_skipped = view.skipped;
  if (view.diagnosis) {
    CaseResult eq;  // judged as equation-error mode is: a force only the logged one holds is there to be named
    eq.spec = given;
    Judge(*view.diagnosis, &eq);
    r.equation_error_first = eq.named_first;
    r.equation_error_named_right = eq.named_right;
    r.equation_error_parameter_right = eq.parameter_right;
    r.details.push_back(view.note);
    for (const std::string& line : eq.details) r.details.push_back("equation-error view: " + line);
    DiagnosisResult verdict;  // judged as the view: the same truth as equation-error mode's
    verdict.effects = view.verdict;
    CaseResult v;
    v.spec = given;
    Judge(verdict, &v);
    r.verdict_first = v.named_first;
    r.verdict_from = view.verdict_from;
    r.verdict_named_right = v.named_right;
    r.verdict_parameter_right = v.parameter_right;
  }
  if (!run_improve) return r;
  r.improve_run = true;
  constexpr unsigned kValidationSeed = 1000;
  const auto read = [&](const fs::path& path) { return ReadMeasurementFor(diagram, path.string(), settings); };
  const MeasurementLog validation = read(write(spec.hidden, seed + kValidationSeed, "validation.csv"));
  ImproveSettings improve;
  improve.measurement = settings;
  const MeasurementLog training_twin = read(write(Hidden::kNone, seed, "training_twin.csv"));
  const MeasurementLog validation_twin = read(write(Hidden::kNone, seed + kValidationSeed, "validation_twin.csv"));
  r.noise_floor = ImproveModel(DiagramDocument(diagram, folder, file), training_twin, &validation_twin, improve)
                      .last_accepted()
                      .rmse_heldout;
  const auto t1 = std::chrono::steady_clock::now();
  const ImproveResult improved = ImproveModel(DiagramDocument(diagram, folder, file), log, &validation, improve);
  r.improve_seconds = Seconds(t1);
  r.heldout_before = improved.first().rmse_heldout;
  r.heldout_after = improved.last_accepted().rmse_heldout;
  r.floor_reached = r.heldout_after <= 1.3 * r.noise_floor && r.heldout_after >= 0.7 * r.noise_floor;
  return r;
}

namespace {

// "yes", or what failed; without improve, the naming and the parameter only.
std::string Verdict(const CaseResult& r) {
  std::vector<std::string> failed;
  if (!r.named_right) failed.emplace_back("name");
  if (!r.parameter_right) failed.emplace_back("parameter");
  if (r.improve_run && !r.floor_reached) failed.emplace_back("floor");
  if (!failed.empty()) return fmt::format("no ({})", fmt::join(failed, ", "));
  return r.improve_run ? "yes" : "named, parameter right (improve not run)";
}

}  // namespace

std::string FormatTable(const std::vector<CaseResult>& results) {
  const bool view = std::any_of(results.begin(), results.end(), [](const CaseResult& r) { return r.equation_error_run; });
  std::string out = fmt::format(
      "| case | named (ranking; (law) = friction-law replacement) | first outside the law | key parameter found "
      "(truth) | held-out RMSE before → after improve (noise floor) [N; m in simulation mode] | compare / improve "
      "[s] | pass |{}\n"
      "|---|---|---|---|---|---|---|{}\n",
      view ? " equation-error view: first (named right, parameter right; its time) | verdict of both views: first "
             "(from; named right, parameter right) |"
           : "",
      view ? "---|---|" : "");
  for (const auto& r : results) {
    std::string named;
    for (const auto& n : r.named) named += (named.empty() ? "" : ", ") + n;
    std::string parameter = "—";
    if (!r.spec.parameter.empty()) {
      parameter = fmt::format("{} {:.4g} ({:.4g})", r.spec.parameter, r.parameter, r.spec.truth);
    }
    const std::string heldout =
        r.improve_run ? fmt::format("{:.4g} → {:.4g} ({:.4g})", r.heldout_before, r.heldout_after, r.noise_floor)
                      : fmt::format("not run ({:.3f})", r.noise_floor);
    const std::string seconds = r.improve_run ? fmt::format("{:.2f} / {:.1f}", r.compare_seconds, r.improve_seconds)
                                              : fmt::format("{:.2f} / —", r.compare_seconds);
    std::string view_cell;
    if (view) {
      view_cell = !r.equation_error_skipped.empty()
                      ? fmt::format(" none: {} |", r.equation_error_skipped)
                      : fmt::format(" {} ({}, {}; {:.2f} s) |",
                                    r.equation_error_first.empty() ? "—" : r.equation_error_first,
                                    r.equation_error_named_right ? "yes" : "no",
                                    r.equation_error_parameter_right ? "yes" : "no", r.equation_error_seconds);
      view_cell += !r.equation_error_skipped.empty()
                       ? " — |"
                       : fmt::format(" {} ({}; {}, {}) |", r.verdict_first.empty() ? "—" : r.verdict_first,
                                     r.verdict_from.empty() ? "neither" : r.verdict_from,
                                     r.verdict_named_right ? "yes" : "no", r.verdict_parameter_right ? "yes" : "no");
    }
    out += fmt::format("| {} | {} | {} | {} | {} | {} | {} |{}\n", r.spec.name,
                       named.empty() ? "nothing" : named, r.named_first.empty() ? "—" : r.named_first, parameter,
                       heldout, seconds,
                       Verdict(r), view_cell);
  }
  return out;
}

}  // namespace mb::independent
