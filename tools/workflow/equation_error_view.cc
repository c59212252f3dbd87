#include "tools/workflow/equation_error_view.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/diagram.h"
#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/units.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr const char* kForceConnector = "equation_error_force";
constexpr const char* kCommandConnector = "equation_error_command";
constexpr const char* kPlantVelocityConnector = "equation_error_plant_velocity";
// The plant's own run must follow f = M·dv/dt + B·v to this share of f's energy to be taken for a rigid body (a
// rigid body's run at 1 kHz follows it to 99.99 %, at 100 Hz to 99.8 %: the central difference's error).
constexpr double kRigidBodyShare = 0.99;

// The block of `element` in the built diagram (an element of the document it was built from).
const Block& BlockOf(const Diagram& d, const std::string& element) {
  return *d.blocks()[static_cast<std::size_t>(d.FindBlock(element))];
}

std::string UnitOfOutput(const Diagram& d, const Endpoint& signal) {
  if (d.FindBlock(signal.element) < 0) return "";
  for (const PortSpec& port : BlockOf(d, signal.element).output_ports()) {
    if (port.name == signal.port) return port.unit;
  }
  return "";
}

}  // namespace

std::string FirstNamedEffect(const DiagnosisResult& d) {
  for (const DiagnosedEffect& e : d.effects) {
    if (std::find(d.friction_law.begin(), d.friction_law.end(), e.effect) == d.friction_law.end()) return e.effect;
  }
  return "";
}

std::pair<std::vector<DiagnosedEffect>, std::string> CombineViews(const DiagnosisResult& position,
                                                                  const DiagnosisResult& force) {
  const auto find = [](const std::vector<DiagnosedEffect>& effects, const std::string& name) {
    return std::find_if(effects.begin(), effects.end(), [&](const DiagnosedEffect& e) { return e.effect == name; });
  };
  std::vector<DiagnosedEffect> both;
  for (const DiagnosedEffect& e : force.effects) {
    const auto in_position = find(position.effects, e.effect);
    // Named by one view only, or named twice (two periods): the first entry stands.
    if (in_position == position.effects.end() || find(both, e.effect) != both.end()) continue;
    const EffectTraits& traits = LookupEffect(e.effect).traits;
    both.push_back(traits.regressor_in_output_band && !traits.command_path ? *in_position : e);
  }
  if (!both.empty()) return {both, "both"};
  const double p = position.effects.empty() ? -1.0 : position.effects.front().score;
  const double f = force.effects.empty() ? -1.0 : force.effects.front().score;
  if (p < 0.0 && f < 0.0) return {{}, ""};
  return f >= p ? std::pair{force.effects, std::string("equation-error view")}
                : std::pair{position.effects, std::string("position view")};
}

namespace {

json RankedJson(const std::vector<DiagnosedEffect>& effects) {
  json ranked = json::array();
  for (const auto& e : effects) {
    ranked.push_back({{"effect", e.effect}, {"score", e.score}, {"parameters", e.ParametersJson()}});
  }
  return ranked;
}

}  // namespace

json EquationErrorView::ToJson() const {
  if (!diagnosis) return {{"skipped", skipped}};
  const json ranked = RankedJson(diagnosis->effects);
  return {{"command_column", command_column},
          {"command_signal", command_signal},
          {"force_signal", force_signal},
          {"mass", mass},
          {"damping", damping},
          {"force_unit", force_unit},
          {"first_named", first_named},
          {"position_first_named", position_first_named},
          {"agrees", first_named == position_first_named},
          {"note", note},
          {"ranked", ranked},
          {"verdict", {{"from", verdict_from}, {"ranked", RankedJson(verdict)}}},
          {"diagnosis", diagnosis->ToJson()}};
}

EquationErrorView DiagnoseEquationErrorView(const DiagnosedComparison& compared, const fs::path& base_directory,
                                            const std::string& source, const MeasurementLog& log,
                                            const MeasurementSettings& settings) {
  EquationErrorView view;
  const auto skip = [&](std::string why) {
    view.skipped = std::move(why);
    return view;
  };
  if (compared.mode != ExperimentMode::kSimulation) return skip("equation-error mode: the comparison is one already");
  if (!compared.diagnosis) return skip("no diagnosis to set it beside");
  if (compared.reactions.empty()) {
    return skip("no log column is the controller's output (the loop's own signal): the commanded force is unknown");
  }
  DiagramDocument document(compared.compared_diagram, base_directory, source);
  const ComparedOutput& primary = compared.after.front();
  const std::optional<Endpoint> position = document.DriverOf({"", primary.connector});
  if (!position || position->is_connector()) return skip(fmt::format("'{}' is no element's output", primary.connector));
  const std::string plant = position->element;
  view.force_unit = document.Axis().force;
  const Diagram closed = BuildDiagram(document.json(), base_directory, source, SchemaCheck::kSkipRevalidation);
  if (closed.FindBlock(plant) < 0) return skip(fmt::format("the plant '{}' is a subsystem, not one block", plant));
  const Block& plant_block = BlockOf(closed, plant);

  // The plant's force input and what drives it.
  std::optional<Endpoint> force;
  for (const PortSpec& port : plant_block.input_ports()) {
    if (QuantityOfUnit(port.unit) != MotionQuantity::kForce) continue;
    if (force) return skip(fmt::format("the plant '{}' has more than one force input", plant));
    force = document.DriverOf({plant, port.name});
  }
  if (!force || force->is_connector()) {
    return skip(fmt::format("the plant '{}' has no force input driven by an element", plant));
  }
  view.force_signal = force->ToString();
  // Its velocity output, whose own run identifies the plant's inverse.
  std::optional<Endpoint> plant_velocity;
  for (const PortSpec& port : plant_block.output_ports()) {
    if (QuantityOfUnit(port.unit) == MotionQuantity::kVelocity) plant_velocity = Endpoint{plant, port.name};
  }
  if (!plant_velocity) return skip(fmt::format("the plant '{}' has no velocity output", plant));

  // Opened at the plant: its position and velocity outputs read the measured ones.
  const std::string velocity_column = DerivedVelocityColumn(settings.position_column);
  for (const PortSpec& port : plant_block.output_ports()) {
    const MotionQuantity quantity = QuantityOfUnit(port.unit);
    const bool is_position = quantity == MotionQuantity::kPosition;
    if (!is_position && quantity != MotionQuantity::kVelocity) continue;
    const std::string name = document.UniqueConnectorName(fmt::format("{}_{}_measured", plant, port.name));
    document.AddConnector({name, "input", port.unit, is_position ? primary.column : velocity_column, ""});
    document.ReadInstead({plant, port.name}, {"", name});
  }
  // The controller's output as it ran.
  const auto& [command_column, command_signal] = compared.reactions.front();
  view.command_column = command_column;
  view.command_signal = command_signal;
  const auto dot = command_signal.find('.');
  const Endpoint command{command_signal.substr(0, dot), command_signal.substr(dot + 1)};
  const std::string command_input = document.UniqueConnectorName(command_column + "_logged");
  document.AddConnector({command_input, "input", UnitOfOutput(closed, command), command_column, ""});
  if (document.ReadInstead(command, {"", command_input}) == 0) {
    return skip(fmt::format("'{}' (log column '{}') feeds no element of the diagram's top level", command_signal,
                            command_column));
  }
  // Outputs: the plant's force, the drive's force, the plant's own velocity (each bound to the position column; only
  // the model side is read).
  for (const DocumentConnector& c : document.Connectors("output")) document.RemoveConnector(c.name);
  const Endpoint drive = compared.drive_force_signal.value_or(*force);
  // The drive's force where it is the replaced signal itself: the logged column.
  const Endpoint drive_read = drive == command ? Endpoint{"", command_input} : drive;
  for (const auto& [name, signal] : {std::pair<std::string, Endpoint>{kForceConnector, *force},
                                     std::pair<std::string, Endpoint>{kCommandConnector, drive_read},
                                     std::pair<std::string, Endpoint>{kPlantVelocityConnector, *plant_velocity}}) {
    document.AddConnector({name, "output", "", primary.column, ""});
    document.Connect(signal, {"", name});
  }
  std::map<std::string, std::string> column_map;
  for (const auto& [connector, column] : settings.column_map) {
    for (const DocumentConnector& c : document.Connectors("input")) {
      if (c.name == connector) column_map.emplace(connector, column);
    }
  }
  ModelComparison opened(document.json(), base_directory, source, log, column_map);
  opened.set_output_filter(settings.derivative_cutoff_hz);
  const std::vector<ComparedOutput> runs = opened.Simulate();
  const Eigen::VectorXd& f = runs[0].model;
  const Eigen::VectorXd& drive_force = runs[1].model;
  const Eigen::VectorXd& t = log.time();

  // The plant's inverse from its own run: f = M·dv/dt + B·v, weighted away from the filter's edges.
  const Eigen::VectorXd weights = opened.FitWeights();
  Eigen::MatrixXd own(f.size(), 2);
  own.col(0) = CentralDifference(t, runs[2].model);
  own.col(1) = runs[2].model;
  const Eigen::VectorXd w = weights.cwiseSqrt();
  const Eigen::MatrixXd weighted = own.array().colwise() * w.array();
  const Eigen::VectorXd wf = f.cwiseProduct(w);
  const Eigen::Vector2d coefficients = weighted.colPivHouseholderQr().solve(wf);
  const double unexplained = (wf - weighted * coefficients).squaredNorm() / std::max(wf.squaredNorm(), 1e-300);
  if (!(1.0 - unexplained >= kRigidBodyShare) || !(coefficients(0) > 0.0)) {
    return skip(fmt::format("the plant '{}' is not a rigid body: its run follows f = M·dv/dt + B·v to {:.2f} % only",
                            plant, 100.0 * (1.0 - unexplained)));
  }
  view.mass = coefficients(0);
  view.damping = coefficients(1);

  // The force residual and its base: the free parameters' sensitivities of the model force (M·a + B·v + what the
  // diagram computes besides the drive: r = f − M·a − B·v, model = drive − r).
  DiagnosisSignals signals = compared.signals;
  const Eigen::VectorXd inverse = view.mass * signals.acceleration + view.damping * signals.velocity;
  signals.residual = f - inverse;
  signals.logged_command = drive_force;
  signals.model_output = drive_force - signals.residual;
  signals.drive_force.resize(0);
  signals.drive_force_response.reset();
  signals.simulate_effect = nullptr;
  BaseRegressors base;
  base.columns.resize(log.rows(), 0);
  bool plant_free = false;
  if (!compared.parameters.empty()) {
    std::vector<std::string> names;
    for (const FreeParameter& p : compared.parameters) {
      const std::string name = p.block + "." + p.parameter;
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      plant_free = plant_free || p.block == plant;
    }
    const std::vector<FreeParameter> params = ResolveFreeParameters(opened.diagram_json(), names);
    const Eigen::MatrixXd jacobian = OutputJacobian(opened, params, GetParameterValues(opened.diagram_json(), params));
    const double largest = jacobian.colwise().norm().maxCoeff();
    for (Eigen::Index j = 0; j < jacobian.cols(); ++j) {
      if (!(jacobian.col(j).norm() > 1e-9 * largest)) continue;  // the plant's own: not in f
      base.columns.conservativeResize(Eigen::NoChange, base.columns.cols() + 1);
      base.columns.col(base.columns.cols() - 1) = -jacobian.col(j);  // the model force is drive − f + M·a + B·v
      base.names.push_back(params[static_cast<std::size_t>(j)].name);
    }
  }
  if (plant_free) {
    base.columns.conservativeResize(Eigen::NoChange, base.columns.cols() + 1);
    base.columns.col(base.columns.cols() - 1) = signals.acceleration;
    base.names.push_back(fmt::format("{} (M·a)", plant));
  }
  DiagnosisOptions options;
  options.regressor_filter_hz = DerivativeCutoffHz(settings, log);
  options.position_unit = compared.diagnosis->position_unit;
  options.catalogue.every_pair = settings.every_pair;
  view.diagnosis = DiagnoseMissingEffects(signals, base, options);
  view.first_named = FirstNamedEffect(*view.diagnosis);
  view.position_first_named = FirstNamedEffect(*compared.diagnosis);
  std::tie(view.verdict, view.verdict_from) = CombineViews(*compared.diagnosis, *view.diagnosis);
  const auto said = [](const std::string& e) { return e.empty() ? std::string("nothing") : "'" + e + "'"; };
  view.note = fmt::format(
      "equation-error view: the force the controller commanded (log column '{}' in place of '{}') against the plant "
      "'{}''s inverse on the measured motion (M = {:.4g}, B = {:.4g}, from its own run) names {} first; the position "
      "view names {}{}",
      view.command_column, view.command_signal, plant, view.mass, view.damping, said(view.first_named),
      said(view.position_first_named), view.first_named == view.position_first_named ? ": both agree" : "");
  std::vector<std::string> verdict;
  for (const DiagnosedEffect& e : view.verdict) verdict.push_back(e.effect);
  view.note += view.verdict.empty() ? "; neither names an effect"
               : view.verdict_from == "both"
                   ? fmt::format("; both name {} (the verdict, each with the parameters of the view that measures it)",
                                 fmt::join(verdict, ", "))
                   : fmt::format("; they name nothing in common, and the {}'s first effect explains the larger share "
                                 "of its residual: the verdict is its {}",
                                 view.verdict_from, fmt::join(verdict, ", "));
  return view;
}

}  // namespace mb
