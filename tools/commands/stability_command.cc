// motionblocks stability DIAGRAM [--gpr MODEL] [--set id.param=value …] [--out DIR]
// The small-gain analysis of the paper's loop (section 4.2): γ terms, ρ (eq. 58), the α_max bound (eq. 62),
// L_x, L_ẋ (eq. 47) and b_μ (Remark 1) once a GPR model is given; Bode data of eq. 6, 7 and 12. Ends with the
// verdict (models/stability/stability.h, StabilityVerdict): certified or not, the failing condition, the largest α.
// Writes stability.json and report.html (Bode magnitude and phase, continuous against the sampled loop).

#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "models/gpr/gpr_io.h"
#include "tools/workflow/loop_from_diagram.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/output_files.h"
#include "tools/report/stability_report.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

struct StabilityCommandOptions {
  std::string diagram;
  std::string gpr;
  std::vector<std::string> overrides;
  std::string out = "out/stability";
  int bode_points = 200;
};

void RunStability(const StabilityCommandOptions& o) {
  RefuseOutputsOverInputs({{"DIAGRAM", o.diagram}, {"--gpr", o.gpr}}, {},
                          {{"--out", o.out, StabilityOutputNames()}});
  const std::vector<ParameterOverride> overrides = ParseOverrides(o.overrides);
  const Diagram diagram = LoadDiagram(o.diagram, overrides);
  std::optional<GprModel> gpr;
  if (!o.gpr.empty()) gpr = LoadGprModel(o.gpr);
  StabilityOptions options;
  options.bode_points = o.bode_points;
  const StabilityReport r = AnalyseStability(diagram, gpr ? &*gpr : nullptr, options);

  WriteStabilityResults(r, diagram.name(), options.impulse_samples, {o.diagram, o.gpr, o.overrides, o.out});

  const PaperLoop& l = r.loop;
  std::cout << fmt::format("stability of {} (Ts = {} ms; M = {} kg, B = {} N·s/m; M_n = {} kg, B_n = {} N·s/m)\n",
                           diagram.name(), l.sample_time * 1e3, l.mass, l.damping, l.nominal_mass,
                           l.nominal_damping);
  std::cout << fmt::format("  inner loop P with C_FB stable: {}; conventional FF/FB/DOB loop stable: {}\n",
                           r.inner_loop_stable ? "yes" : "NO", r.dob_loop_stable ? "yes" : "NO");
  std::cout << fmt::format("  eq. 58 (paper) ρ = {}; consistent ρ' = {}; eq. 62: {}\n",
                           StabilityTermText(r.rho_paper), StabilityTermText(r.rho_consistent),
                           AlphaBoundText(r.alpha_max_bound_paper, r.has_gpr));
  std::cout << fmt::format("  DOB loop closed, GP path fed back: ρ = {}; {}\n", StabilityTermText(r.rho_dob),
                           AlphaBoundText(r.alpha_max_bound_dob, r.has_gpr));
  if (r.has_gpr) {
    std::cout << fmt::format("  GPR: L_x = {}, L_ẋ = {}, b_μ = {}\n", StabilityTermText(r.dob.lipschitz_x, "N/m"),
                             StabilityTermText(r.dob.lipschitz_xdot, "N·s/m"), StabilityTermText(r.b_mu, "N"));
  }
  for (const auto& note : r.notes) std::cout << "  note: " << note << "\n";

  std::cout << "wrote " << (fs::path(o.out) / "stability.json").string() << " and report.html\n";
  std::cout << "verdict: " << r.verdict.line << "\n";
}

void SetupStabilityCommand(CLI::App& app) {
  auto o = std::make_shared<StabilityCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "stability", "Small-gain stability of the paper's DOB loop with the GP path (section 4.2) and Bode data");
  cmd->add_option("diagram", o->diagram,
                  "diagram with a plant, a PD and optionally a dob, found by block type or \"roles\" "
                  "(tools/workflow/loop_from_diagram.h)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--gpr", o->gpr, "TISO-GPR model file (fit-gpr): adds L_x, L_ẋ, b_μ and the α_max bound")
      ->check(CLI::ExistingFile);
  AddSetOption(cmd, &o->overrides, "override a parameter: block.param=value (repeatable)");
  cmd->add_option("--out", o->out, "output folder")->capture_default_str();
  cmd->add_option("--bode-points", o->bode_points, "log-spaced frequencies of the Bode data")
      ->capture_default_str()
      ->check(CLI::Range(2, 100000));
  cmd->callback([o] { RunStability(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(stability, {"stability", CommandGroup::kLearnedCompensation, &SetupStabilityCommand, false})

}  // namespace mb
