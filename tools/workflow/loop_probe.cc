#include "tools/workflow/loop_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "engine/block_roles.h"
#include "engine/diagram_document.h"
#include "engine/units.h"
#include "models/diagnosis/measurement_log.h"
#include "models/diagnosis/signal_processing.h"
#include "tools/workflow/suggest.h"

namespace mb {
namespace {

constexpr double kProbeShare = 1e-4;        // δ as a share of the RMS force driving the plant
constexpr double kMovingShare = 0.1;        // moving: |v| above this share of its maximum
constexpr double kEnergyKept = 1.0 - 1e-6;  // of the impulse response's energy
// A load's responses to a push either way agree within this share when the diagram is smooth there (central
// differences: they differ by O(δ) relative); a switching law makes them differ by O(1).
constexpr double kTangentTolerance = 0.05;

// [first, last) of the longest stretch where |v| ≥ share × max |v|.
std::pair<Eigen::Index, Eigen::Index> LongestMovingStretch(const Eigen::VectorXd& velocity, double share) {
  const double threshold = share * velocity.cwiseAbs().maxCoeff();
  std::pair<Eigen::Index, Eigen::Index> best{0, 0};
  Eigen::Index start = -1;
  for (Eigen::Index i = 0; i <= velocity.size(); ++i) {
    const bool moving = i < velocity.size() && std::abs(velocity(i)) >= threshold && threshold > 0.0;
    if (moving && start < 0) start = i;
    if (!moving && start >= 0) {
      if (i - start > best.second - best.first) best = {start, i};
      start = -1;
    }
  }
  return best;
}

// The compared output's exact response to loads at `port` (LoopResponse::Simulator): per column, the diagram with
// the column, scaled to a small force, subtracted at the port (a load: a force the drive must supply), simulated
// along the record, minus the nominal run, over the scale. The columns run in parallel, each on its own copy.
LoopResponse::Simulator LoadSimulator(const ModelComparison& comparison, const ComparedOutput& nominal,
                                      const Endpoint& port, double delta) {
  DiagramDocument d(comparison.diagram_json(), comparison.base_directory(), comparison.source());
  const std::string column = "diagnosis_load";
  d.AddConnector({column, "input", "", column, ""});
  d.SubtractInto(port, Endpoint{"", column}, "diagnosis_load_sum");
  std::map<std::string, std::string> columns = comparison.ColumnMap();
  columns[column] = column;
  return [json = d.json(), base = comparison.base_directory(), source = comparison.source(), log = comparison.log(),
          columns, column, model = nominal.model, delta](const Eigen::MatrixXd& loads) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(loads.rows(), loads.cols());
    std::vector<Eigen::VectorXd> pushed(static_cast<std::size_t>(2 * loads.cols()));
    // Each column pushed both ways (central differences); a response that is not odd in the push is no tangent: the
    // diagram switches (a stick–slip law's stick band, a saturation reached) within the push, and the column is NaN —
    // as it is when a pushed run fails, so that the diagnosis keeps the linearised column rather than being lost.
    tbb::parallel_for(Eigen::Index{0}, 2 * loads.cols(), [&](Eigen::Index k) {
      const Eigen::Index j = k / 2;
      const double rms = std::sqrt(loads.col(j).squaredNorm() / static_cast<double>(loads.rows()));
      if (!(rms > 0.0) || !std::isfinite(rms)) return;
      const double scale = (k % 2 == 0 ? 1.0 : -1.0) * delta / rms;
      MeasurementLog with = log;
      with.AddColumn(column, scale * loads.col(j));
      try {
        const ModelComparison run(json, base, source, with, columns);
        pushed[static_cast<std::size_t>(k)] = (run.Simulate().front().model - model) / scale;
      } catch (const std::exception&) {  // the pushed diagram failed to simulate: no tangent, the linearised response
        pushed[static_cast<std::size_t>(k)] =
            Eigen::VectorXd::Constant(loads.rows(), std::numeric_limits<double>::quiet_NaN());
      }
    });
    for (Eigen::Index j = 0; j < loads.cols(); ++j) {
      const Eigen::VectorXd& up = pushed[static_cast<std::size_t>(2 * j)];
      const Eigen::VectorXd& down = pushed[static_cast<std::size_t>(2 * j + 1)];
      if (up.size() != loads.rows() || down.size() != loads.rows()) continue;
      const bool odd = (up - down).norm() <= kTangentTolerance * (up + down).norm();
      out.col(j) = odd ? (0.5 * (up + down)).eval()
                       : Eigen::VectorXd::Constant(loads.rows(), std::numeric_limits<double>::quiet_NaN());
    }
    return out;
  };
}

}  // namespace

std::optional<std::string> PlantElement(const DiagramDocument& d, std::string* why) {
  std::vector<std::string> plants;
  for (const std::string& type : BlockRoleRegistry::Global().TypesWithLoopRole("plant")) {
    for (const std::string& element : d.ElementsOfType(type)) plants.push_back(element);
  }
  if (plants.size() == 1) return plants.front();
  *why = plants.empty() ? "the diagram has no plant (no element of a type with the loop role \"plant\")"
                        : fmt::format("the diagram has {} plants ({}); which one the effects act on is not known",
                                      plants.size(), fmt::join(plants, ", "));
  return std::nullopt;
}

std::optional<Endpoint> PlantForcePort(const DiagramDocument& d, std::string* why) {
  const std::optional<std::string> plant = PlantElement(d, why);
  if (!plant) return std::nullopt;
  std::vector<Endpoint> driven;
  for (const Connection& c : d.Connections()) {
    if (c.end.element == *plant) driven.push_back(c.end);
  }
  if (driven.size() == 1) return driven.front();
  for (const char* port : {"f", "u"}) {
    for (const Endpoint& e : driven) {
      if (e.port == port) return e;
    }
  }
  *why = fmt::format("plant '{}' has {} driven inputs and none named f or u: which one is its force is not known",
                     *plant, driven.size());
  return std::nullopt;
}

std::function<Eigen::VectorXd(const EffectInstance&)> EffectSimulator(const ModelComparison& comparison,
                                                                      const ComparedOutput& nominal,
                                                                      const std::optional<Endpoint>& drive_force) {
  // What every call reads, shared by the callable's copies (the diagnosis copies its signals).
  struct Fixed {
    nlohmann::json diagram;
    std::filesystem::path base;
    std::string source;
    MeasurementLog log;
    std::map<std::string, std::string> columns;
    std::string output;
    Eigen::VectorXd model;
    std::optional<Endpoint> drive_force;
  };
  auto fixed = std::make_shared<const Fixed>(Fixed{comparison.diagram_json(), comparison.base_directory(),
                                                   comparison.source(), comparison.log(), comparison.ColumnMap(),
                                                   nominal.connector, nominal.model, drive_force});
  return [fixed](const EffectInstance& effect) -> Eigen::VectorXd {
    DiagnosedEffect diagnosed;
    diagnosed.effect = effect.name;
    diagnosed.parameters = effect.parameters;
    const nlohmann::json amended = SuggestAmendedDiagram(fixed->diagram, diagnosed, fixed->output, fixed->drive_force);
    const ModelComparison run(amended, fixed->base, fixed->source, fixed->log, fixed->columns);
    return run.Simulate().front().model - fixed->model;
  };
}

LoopProbe ProbeLoop(const ModelComparison& comparison, const ComparedOutput& nominal,
                    const std::vector<std::pair<std::string, Eigen::VectorXd>>& own, const Eigen::VectorXd& velocity,
                    const std::optional<Endpoint>& drive_force) {
  LoopProbe out;
  const auto not_probed = [&](const std::string& why) {
    out.note = "simulation mode: the candidate forces are fitted to the output error as they are, not through the "
               "closed loop, because " + why;
    return out;
  };
  DiagramDocument d(comparison.diagram_json(), comparison.base_directory(), comparison.source());
  std::string why;
  const std::optional<Endpoint> port = PlantForcePort(d, &why);
  if (!port) return not_probed(why);
  const std::optional<Endpoint> driver = d.DriverOf(*port);
  double force_rms = 0.0;
  for (const auto& [name, signal] : own) {
    if (driver && name == driver->ToString() && signal.size() > 0) {
      force_rms = std::sqrt(signal.squaredNorm() / static_cast<double>(signal.size()));
    }
  }
  if (!(force_rms > 0.0)) return not_probed(fmt::format("the force into '{}' is not known or zero", port->ToString()));
  const auto [first, last] = LongestMovingStretch(velocity, kMovingShare);
  if (last - first < 2) return not_probed("the axis does not move");
  const Eigen::VectorXd& t = comparison.log().time();
  const double dt = MedianTimeStep(t);
  const double delta = kProbeShare * force_rms;
  const double at = t(first) - 0.5 * dt;
  const std::string step = d.Add({"loop_probe", "step", {{"time", at}, {"initial", 0.0}, {"final", delta}},
                                  std::nullopt, "a small force step probing the closed loop"});
  d.SumInto(*port, d.OutputOf(step), "loop_probe_sum");
  const ModelComparison probe(d.json(), comparison.base_directory(), comparison.source(), comparison.log(),
                              comparison.ColumnMap());
  const std::vector<ComparedOutput> probed = probe.Simulate();
  // A load: the force the drive must supply beyond the model's (the sign of every effect's coefficient in
  // equation-error mode, where the residual is the measured force minus the model's) acts against the step's push.
  const Eigen::VectorXd s = -(probed.front().model - nominal.model) / delta;
  const Eigen::Index n = s.size();
  // While the axis moves the loop is the linear one (a Coulomb force is constant then); where it sticks again the
  // force no longer moves it, and the response jumps at every later stop: the response is read over the stretch.
  const auto impulse_response = [&](const Eigen::VectorXd& step_response) -> std::shared_ptr<const LoopResponse> {
    Eigen::VectorXd h(last - first);
    for (Eigen::Index k = 0; k < h.size(); ++k) {
      h(k) = step_response(first + k) - (first + k > 0 ? step_response(first + k - 1) : 0.0);
    }
    const double energy = h.squaredNorm();
    if (!std::isfinite(energy) || !(energy > 0.0)) return nullptr;
    double kept = 0.0;
    Eigen::Index length = 0;
    for (; length < h.size() && kept < kEnergyKept * energy; ++length) kept += h(length) * h(length);
    return std::make_shared<const LoopResponse>(h.head(length).eval(), n);
  };
  const std::shared_ptr<const LoopResponse> linearised = impulse_response(s);
  if (!linearised) return not_probed("the output does not respond to a force at the plant");
  auto loop = std::make_shared<LoopResponse>(*linearised);
  loop->set_simulator(LoadSimulator(comparison, nominal, *port, delta));
  out.loop = std::move(loop);
  const Eigen::Index length = out.loop->impulse_response().size();
  if (drive_force) {  // the controller's reaction to the same load, read on the probe's own signals
    const std::string name = drive_force->ToString();
    using Signals = std::vector<std::pair<std::string, Eigen::VectorXd>>;
    const auto find = [&](const Signals& signals) -> const Eigen::VectorXd* {
      for (const auto& [signal_name, signal] : signals) {
        if (signal_name == name && signal.size() == n) return &signal;
      }
      return nullptr;
    };
    const Signals probed_signals = probe.SimulateBlockOutputs();
    const Eigen::VectorXd* with = find(probed_signals);
    const Eigen::VectorXd* without = find(own);
    if (with != nullptr && without != nullptr) out.drive_force = impulse_response(-(*with - *without) / delta);
  }
  out.note = fmt::format(
      "simulation mode: every candidate force is fitted to the output error through the closed loop, measured on the "
      "diagram (a force step of {:.3g} into '{}' at t = {:.4g} s, while the axis moves): a constant load moves the "
      "output by {:.4g} {} per unit of force, the response lasts {:.4g} s; the coefficients are forces",
      delta, port->ToString(), at, out.loop->static_gain(), nominal.unit, static_cast<double>(length) * dt);
  return out;
}

DriveForce ModelDriveForce(const DiagramDocument& d, const std::vector<ComparedOutput>& outputs,
                           const std::vector<std::pair<std::string, Eigen::VectorXd>>& own,
                           const std::vector<std::pair<std::string, std::string>>& reactions) {
  DriveForce out;
  const auto own_signal = [&](const std::string& name) -> const Eigen::VectorXd* {
    for (const auto& [signal_name, signal] : own) {
      if (signal_name == name && signal.size() > 0) return &signal;
    }
    return nullptr;
  };
  for (std::size_t o = 1; o < outputs.size(); ++o) {
    if (QuantityOfUnit(outputs[o].unit) != MotionQuantity::kForce) continue;
    const std::optional<Endpoint> driver = d.DriverOf({"", outputs[o].connector});
    if (!driver || driver->is_connector()) continue;
    out.force = outputs[o].model;
    out.source = driver;
    out.note = fmt::format("simulation mode: the model's drive force ŷ, which a force constant multiplies, is the "
                           "compared output '{}' [{}]",
                           outputs[o].connector, outputs[o].unit);
    return out;
  }
  for (const auto& [column, name] : reactions) {
    if (QuantityOfUnit(ColumnUnit(column)) != MotionQuantity::kForce) continue;
    const std::size_t dot = name.rfind('.');
    if (dot == std::string::npos) continue;
    if (const Eigen::VectorXd* signal = own_signal(name)) {
      out.force = *signal;
      out.source = Endpoint{name.substr(0, dot), name.substr(dot + 1)};
      out.note = fmt::format("simulation mode: the model's drive force ŷ, which a force constant multiplies, is '{}', "
                             "the diagram's signal that the logged command '{}' is",
                             name, column);
      return out;
    }
  }
  // Not the net force into the plant: for a rigid body it is M·a, and a force constant's product of it would be the
  // inertia's product of the same factor under another name.
  out.note = "simulation mode: the force constant's and the command path's effects are not proposed, since the model's "
             "drive force is not known: compare the drive's force as an output in N (an output connector fed by the "
             "controller's force), or log its command in a column in N";
  return out;
}

}  // namespace mb
