#include "tools/report/stability_report.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include <fmt/format.h>

#include "tools/report/output_files.h"
#include "tools/report/report.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

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

void AddBode(HtmlReport& html, const fs::path& out, const std::string& stem, const std::string& what,
             const std::string& unit, const BodeCurves& continuous, const BodeCurves& discrete) {
  html.AddFigure({stem + "_magnitude.png", what + ": magnitude", "frequency [Hz]", "|G| [dB " + unit + "]",
                  {continuous.magnitude, discrete.magnitude}, true},
                 out);
  html.AddFigure({stem + "_phase.png", what + ": phase", "frequency [Hz]", "phase [deg]",
                  {continuous.phase, discrete.phase}, true},
                 out);
}

}  // namespace

std::string StabilityTermText(double value, const char* unit) {
  if (std::isnan(value)) return "—";
  if (std::isinf(value)) return value > 0 ? "+∞" : "−∞";
  return fmt::format("{:.4g}{}{}", value, *unit ? " " : "", unit);
}

std::vector<std::string> StabilityOutputNames() {
  std::vector<std::string> names{"stability.json", "report.html"};
  for (const auto& name : FigureFileNames("*.png")) names.push_back(name);
  return names;
}

nlohmann::json WriteStabilityResults(const StabilityReport& r, const std::string& diagram_name, int impulse_samples,
                                     const StabilityFiles& files) {
  const fs::path& out = files.out;
  fs::create_directories(out);
  nlohmann::json j = ToJson(r);
  j["diagram"] = fs::absolute(files.diagram).string();
  j["gpr_model"] = files.gpr;
  j["overrides"] = files.overrides;
  WriteJsonFile(j, out / "stability.json");

  HtmlReport html(fmt::format("motionblocks stability: {}", diagram_name));
  html.Paragraph(fmt::format(
      "Small-gain analysis of section 4.2 for {} (l1 norms of the sampled loop's impulse responses, {} samples). "
      "The 'paper' column is eq. 54–62 as printed; the 'DOB loop' column closes the conventional FF/FB/DOB loop "
      "and feeds back only the GP path (models/stability/stability.h explains both).",
      files.diagram, impulse_samples));
  html.Paragraph("Verdict: " + r.verdict.line);
  const auto row = [](const std::string& name, const std::string& unit, double paper, double dob) {
    return std::vector<std::string>{name, unit, StabilityTermText(paper), StabilityTermText(dob)};
  };
  html.Table({"term", "unit", "paper", "DOB loop"},
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
  if (r.has_gpr) html.Paragraph(fmt::format("b_μ (Remark 1, eq. 50) = {}.", StabilityTermText(r.b_mu, "N")));
  for (const auto& note : r.notes) html.Paragraph(note);

  AddBode(html, out, "eq6_reference_to_position", "Eq. 6, reference to position", "",
          Curves(r.bode, "continuous (s = jω)", [](const BodePoint& b) { return b.xd_to_x_continuous; }),
          Curves(r.bode, "sampled loop (z = e^{jωTs})", [](const BodePoint& b) { return b.xd_to_x_discrete; }));
  AddBode(html, out, "eq7_disturbance_to_position", "Eq. 7, disturbance to position", "m/N",
          Curves(r.bode, "continuous (s = jω)", [](const BodePoint& b) { return b.d_to_x_continuous; }),
          Curves(r.bode, "sampled loop (z = e^{jωTs})", [](const BodePoint& b) { return b.d_to_x_discrete; }));
  AddBode(html, out, "eq12_disturbance_to_estimate", "Eq. 12, disturbance to DOB estimate", "",
          Curves(r.bode, "continuous (s = jω)", [](const BodePoint& b) { return b.d_to_dhat_continuous; }),
          Curves(r.bode, "sampled loop (z = e^{jωTs})", [](const BodePoint& b) { return b.d_to_dhat_discrete; }));
  html.Write(out / "report.html");
  return j;
}

}  // namespace mb
