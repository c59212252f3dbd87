// motionblocks stability DIAGRAM [--gpr MODEL] [--set id.param=value …] [--out DIR]
// The small-gain analysis of the paper's loop (section 4.2): γ terms, ρ (eq. 58), the α_max bound (eq. 62),
// L_x, L_ẋ (eq. 47) and b_μ (Remark 1) once a GPR model is given; Bode data of eq. 6, 7 and 12. Ends with the
// verdict (models/stability/stability.h, StabilityVerdict): certified or not, the failing condition, the largest α.
// Writes stability.json and report.html (Bode magnitude and phase, continuous against the sampled loop).

#include <algorithm>
#include <cmath>
#include <complex>
#include <iostream>
#include <limits>
#include <numbers>
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
#include "tools/report/report.h"

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

std::string Show(double value, const char* unit = "") {
  if (std::isnan(value)) return "—";
  if (std::isinf(value)) return value > 0 ? "+∞" : "−∞";
  return fmt::format("{:.4g}{}{}", value, *unit ? " " : "", unit);
}

// |G| in dB and ∠G in degrees of one transfer function across the Bode points.
struct BodeCurves {
  Series magnitude, phase;
};

template <typename Pick>
BodeCurves Curves(const std::vector<BodePoint>& bode, const std::string& label, Pick pick) {
  BodeCurves c{{{}, {}, label}, {{}, {}, label}};
  for (const BodePoint& b : bode) {
    const std::complex<double> g = pick(b);
    c.magnitude.x.push_back(b.frequency_hz);
    c.magnitude.y.push_back(20.0 * std::log10(std::max(std::abs(g), 1e-300)));
    c.phase.x.push_back(b.frequency_hz);
    c.phase.y.push_back(std::arg(g) * 180.0 / std::numbers::pi);
  }
  return c;
}

void AddBode(HtmlReport& report, const fs::path& out, const std::string& stem, const std::string& what,
             const std::string& unit, const BodeCurves& continuous, const BodeCurves& discrete) {
  report.AddFigure({stem + "_magnitude.png", what + ": magnitude", "frequency [Hz]", "|G| [dB " + unit + "]",
                    {continuous.magnitude, discrete.magnitude}, true},
                   out);
  report.AddFigure({stem + "_phase.png", what + ": phase", "frequency [Hz]", "phase [deg]",
                    {continuous.phase, discrete.phase}, true},
                   out);
}

// The files stability writes into --out: refused over an input before any work (RefuseOutputsOverInputs).
std::vector<std::string> StabilityOutputNames() {
  std::vector<std::string> names{"stability.json", "report.html"};
  for (const auto& name : FigureFileNames("*.png")) names.push_back(name);
  return names;
}

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

  const fs::path out(o.out);
  fs::create_directories(out);
  nlohmann::json j = ToJson(r);
  j["diagram"] = fs::absolute(o.diagram).string();
  j["gpr_model"] = o.gpr;
  j["overrides"] = o.overrides;
  WriteJsonFile(j, out / "stability.json");

  const PaperLoop& l = r.loop;
  std::cout << fmt::format("stability of {} (Ts = {} ms; M = {} kg, B = {} N·s/m; M_n = {} kg, B_n = {} N·s/m)\n",
                           diagram.name(), l.sample_time * 1e3, l.mass, l.damping, l.nominal_mass,
                           l.nominal_damping);
  std::cout << fmt::format("  inner loop P with C_FB stable: {}; conventional FF/FB/DOB loop stable: {}\n",
                           r.inner_loop_stable ? "yes" : "NO", r.dob_loop_stable ? "yes" : "NO");
  std::cout << fmt::format("  eq. 58 (paper) ρ = {}; consistent ρ' = {}; eq. 62: {}\n", Show(r.rho_paper),
                           Show(r.rho_consistent), AlphaBoundText(r.alpha_max_bound_paper, r.has_gpr));
  std::cout << fmt::format("  DOB loop closed, GP path fed back: ρ = {}; {}\n", Show(r.rho_dob),
                           AlphaBoundText(r.alpha_max_bound_dob, r.has_gpr));
  if (r.has_gpr) {
    std::cout << fmt::format("  GPR: L_x = {}, L_ẋ = {}, b_μ = {}\n", Show(r.dob.lipschitz_x, "N/m"),
                             Show(r.dob.lipschitz_xdot, "N·s/m"), Show(r.b_mu, "N"));
  }
  for (const auto& note : r.notes) std::cout << "  note: " << note << "\n";

  HtmlReport report(fmt::format("motionblocks stability: {}", diagram.name()));
  report.Paragraph(fmt::format(
      "Small-gain analysis of section 4.2 for {} (l1 norms of the sampled loop's impulse responses, {} samples). "
      "The 'paper' column is eq. 54–62 as printed; the 'DOB loop' column closes the conventional FF/FB/DOB loop "
      "and feeds back only the GP path (models/stability/stability.h explains both).",
      o.diagram, options.impulse_samples));
  report.Paragraph("Verdict: " + r.verdict.line);
  const auto row = [](const std::string& name, const std::string& unit, double paper, double dob) {
    return std::vector<std::string>{name, unit, Show(paper), Show(dob)};
  };
  report.Table({"term", "unit", "paper", "DOB loop"},
               {row("γ_d→x", "m/N", r.paper.gamma_d_to_x, r.dob.gamma_d_to_x),
                row("γ_xd→x", "", r.paper.gamma_xd_to_x, r.dob.gamma_xd_to_x),
                row("γ_q = ‖Q∘P_n⁻¹‖₁", "N/m", r.paper.gamma_q, r.dob.gamma_q),
                row("γ_x→u", "N/m", r.paper.gamma_x_to_u, r.dob.gamma_x_to_u),
                row("γ_ẋ = ‖F_ẋ‖₁", "1/s", r.paper.gamma_xdot, r.dob.gamma_xdot),
                row("γ_g = ‖F_gp‖₁", "", r.paper.gamma_g, r.dob.gamma_g),
                row("L_x (eq. 47)", "N/m", r.paper.lipschitz_x, r.dob.lipschitz_x),
                row("L_ẋ (eq. 47)", "N·s/m", r.paper.lipschitz_xdot, r.dob.lipschitz_xdot),
                row("α (f_gp weight)", "", r.paper.alpha_max, r.dob.alpha_max),
                row("ρ (eq. 58)", "", r.rho_paper, r.rho_dob),
                {"α_max bound (eq. 62)", "", AlphaBoundText(r.alpha_max_bound_paper, r.has_gpr),
                 AlphaBoundText(r.alpha_max_bound_dob, r.has_gpr)}});
  if (r.has_gpr) report.Paragraph(fmt::format("b_μ (Remark 1, eq. 50) = {}.", Show(r.b_mu, "N")));
  for (const auto& note : r.notes) report.Paragraph(note);

  AddBode(report, out, "eq6_reference_to_position", "Eq. 6, reference to position", "",
          Curves(r.bode, "continuous (s = jω)", [](const BodePoint& b) { return b.xd_to_x_continuous; }),
          Curves(r.bode, "sampled loop (z = e^{jωTs})", [](const BodePoint& b) { return b.xd_to_x_discrete; }));
  AddBode(report, out, "eq7_disturbance_to_position", "Eq. 7, disturbance to position", "m/N",
          Curves(r.bode, "continuous (s = jω)", [](const BodePoint& b) { return b.d_to_x_continuous; }),
          Curves(r.bode, "sampled loop (z = e^{jωTs})", [](const BodePoint& b) { return b.d_to_x_discrete; }));
  AddBode(report, out, "eq12_disturbance_to_estimate", "Eq. 12, disturbance to DOB estimate", "",
          Curves(r.bode, "continuous (s = jω)", [](const BodePoint& b) { return b.d_to_dhat_continuous; }),
          Curves(r.bode, "sampled loop (z = e^{jωTs})", [](const BodePoint& b) { return b.d_to_dhat_discrete; }));
  report.Write(out / "report.html");
  std::cout << "wrote " << (out / "stability.json").string() << " and report.html\n";
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
