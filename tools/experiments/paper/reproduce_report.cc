// reproduce, step 9: report.html (the tables beside the paper's and the figures) and results.json.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tools/experiments/paper/reproduce_context.h"
#include "tools/report/output_files.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::vector<double> Scaled(const std::vector<double>& v, double k) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [k](double a) { return k * a; });
  return out;
}

Figure MakeFigure(std::string file, std::string title, std::string xlabel, std::string ylabel) {
  return Figure{std::move(file), std::move(title), std::move(xlabel), std::move(ylabel), {}};
}

Series MakeSeries(std::vector<double> x, std::vector<double> y, std::string label, std::string style = "lines") {
  return Series{std::move(x), std::move(y), std::move(label), std::move(style)};
}

std::string Fixed(double v, int digits) { return fmt::format("{:.{}f}", v, digits); }

std::string Percent(double ours, double paper) { return fmt::format("{:+.1f} %", 100.0 * (ours - paper) / paper); }

void AddTables(const ReproduceContext& c, HtmlReport& report) {
  const ReproduceOptions& o = c.options;
  const int jobs = c.jobs;
  report.Paragraph(fmt::format(
      "Reproduction of Jung et al., TISO-GPR integrated with disturbance observers (reference/paper-tisogpr-dob.txt), "
      "on the simulated linear-motor twin (docs/paper.md), from diagrams/paper/ ({} mode: {} scan velocities, {} "
      "MAP start(s) per fit; {} threads, {:.1f} s).",
      o.quick ? "quick" : "full", c.scans.size(), o.quick ? 1 : 3, jobs, c.Elapsed()));
  report.Heading("Where our figures differ from the paper's, and why");
  for (const auto& f : c.findings) report.Paragraph(f);

  report.Heading("Table 1: model RMSE over the full operating range [N]");
  {
    std::vector<std::vector<std::string>> rows;
    for (int kernel = 0; kernel < 2; ++kernel) {
      const std::string kname = kKernelName[kernel];
      std::vector<std::string> row = {kname + " (ours, vs true d)"};
      for (int k = 0; k < 3; ++k) row.push_back(Fixed(c.table1_ours.at(kname)[static_cast<std::size_t>(k)], 4));
      rows.push_back(row);
      row = {kname + " (ours, vs DOB estimate)"};
      for (int k = 0; k < 3; ++k)
        row.push_back(Fixed(c.table1["against_dob_estimate"][kname][kWindowName[k]].get<double>(), 4));
      rows.push_back(row);
      row = {kname + " (ours, paper-size N, vs true d)"};
      for (int k = 0; k < 3; ++k)
        row.push_back(Fixed(c.table1["paper_size_fits"][kname][kWindowName[k]].get<double>(), 4));
      rows.push_back(row);
      row = {kname + " (paper)"};
      for (int k = 0; k < 3; ++k) row.push_back(Fixed(kPaperTable1.at(kname)[static_cast<std::size_t>(k)], 4));
      rows.push_back(row);
    }
    report.Table({"kernel", "D(1) 125 mm", "D(2) 225 mm", "D(3) 325 mm"}, rows);
    std::vector<std::vector<std::string>> sizes;
    for (int k = 0; k < 3; ++k) {
      sizes.push_back({kWindowName[k], fmt::format("{}", c.full[k].x.size()),
                       fmt::format("{}", c.paper_size[k].x.size()), fmt::format("{}", kPaperDatasetSize[k])});
    }
    report.Table({"window", "samples (ours, all)", "paper-size downsample", "paper"}, sizes);
  }
  report.Heading("Table 2: tracking RMSE on the Fig. 9 profile [µm]");
  {
    const double conv = c.RmseUm(PaperCase::kConventional), ds = c.RmseUm(PaperCase::kDs), ps = c.RmseUm(PaperCase::kPs);
    const double paper_conv = kPaperTable2.at("conventional"), paper_ds = kPaperTable2.at("DS"),
                 paper_ps = kPaperTable2.at("PS");
    report.Table({"", "conv", "DS", "PS"},
                 {{"ours", Fixed(conv, 3), Fixed(ds, 3), Fixed(ps, 3)},
                  {"paper", Fixed(paper_conv, 3), Fixed(paper_ds, 3), Fixed(paper_ps, 3)},
                  {"difference", Percent(conv, paper_conv), Percent(ds, paper_ds), Percent(ps, paper_ps)},
                  {"ablation: PS trained on the true d", "", "", Fixed(c.RmseUm(PaperCase::kPsTrueDisturbance), 3)},
                  {"PS trained on the smoothed estimate (measured signals)", "", "",
                   Fixed(c.RmseUm(PaperCase::kPsSmoothed), 3)}});
  }
  report.Heading(
      fmt::format("Section 5.3: payload {} kg (moving mass doubled), models not retrained [µm]", kPayloadMass));
  report.Table({"", "conv", "DS", "PS"},
               {{"without payload", Fixed(c.RmseUm(PaperCase::kConventional), 3), Fixed(c.RmseUm(PaperCase::kDs), 3),
                 Fixed(c.RmseUm(PaperCase::kPs), 3)},
                {"with payload", Fixed(c.RmseUm(PaperCase::kConventionalPayload), 3),
                 Fixed(c.RmseUm(PaperCase::kDsPayload), 3), Fixed(c.RmseUm(PaperCase::kPsPayload), 3)}});
  {
    const json& study = c.payload_json["sweep"];
    Figure f = MakeFigure("payload_study.png", "Tracking RMSE on Fig. 9 against the added moving mass (not retrained)",
                          "payload [kg] (moving mass 0.2621 kg)", "tracking RMSE [µm]");
    for (const char* name : {"conventional", "DS", "PS"}) {
      f.series.push_back(MakeSeries(study["payload_mass_kg"].get<std::vector<double>>(),
                                    study[name].get<std::vector<double>>(), name, "linespoints"));
    }
    report.AddFigure(f, o.out);
  }
  report.Heading("Stability (section 4.2) and cost per control step");
  {
    std::vector<std::vector<std::string>> rows;
    for (int kernel = 0; kernel < 2; ++kernel) {
      const json& s = c.stability[kKernelName[kernel]];
      auto num = [](const json& v) { return v.is_null() ? std::string("∞") : fmt::format("{:.4g}", v.get<double>()); };
      rows.push_back({kKernelName[kernel], fmt::format("{:.3g}", c.stability["alpha"].get<double>()),
                      num(s["dob"]["lipschitz_x"]), num(s["dob"]["lipschitz_xdot"]), num(s["dob"]["rho"]),
                      num(s["dob"]["alpha_max_bound"]), num(s["paper"]["rho"]),
                      fmt::format("{:.0f}", c.timing[kKernelName[kernel]]["posterior_mean_ns"].get<double>()),
                      fmt::format("{}", c.timing[kKernelName[kernel]]["features"].get<int>())});
    }
    report.Table({"model (D2)", "α", "L_x [N/m]", "L_ẋ [N·s/m]", "ρ (DOB loop closed)", "α bound (DOB loop closed)",
                  "ρ eq. 58 as printed", "μ per step [ns]", "features M"},
                 rows);
    report.Paragraph(
        "ρ as printed (eq. 58) bounds the DOB through ‖C_FB‖₁ and is ≥ 1 for every PD loop (docs/paper.md), so it "
        "certifies nothing; with the conventional FF/FB/DOB loop closed and only the GP path fed back, the same "
        "small-gain argument gives ρ = γ_d→x·γ_g·α·K. μ per step: GprModel::PredictPosteriorMean, the call the gpr "
        "block makes at each 1 ms hit (O(M), no allocation), timed over the Fig. 9 inputs; the control period is "
        "10⁶ ns.");
  }
}

void AddConfidenceTable(const ReproduceContext& c, HtmlReport& report) {
  const json& k = c.confidence;
  const json& rmse = k["tracking_rmse"];
  const json& outside = k["tracking_rmse_outside_D2"];
  const auto um = [](const json& v) { return Fixed(v.get<double>(), 3); };
  report.Heading("Variance-aware compensation: α(x, ẋ) = α_max·g(σ²/σ_f²) (beyond the paper) [µm]");
  report.Paragraph(fmt::format(
      "The gpr block scales its posterior mean by g = clip(1 − σ²(x, ẋ)/σ_f², 0, 1) (confidence_weighting, "
      "blocks/gpr.h): 1 where the training data pin the posterior down, falling towards the share of the prior "
      "variance still known where they do not. Same Fig. 9 runs as Table 2 (α_max = {}); \"outside D(2)\": the "
      "samples with x outside the 225 mm training window. \"PS, α_max = {:.3g}\": the highest α_max ≤ 0.99 (eq. 53: α < 1) with ρ < 1 "
      "(10 % margin) in the analysis with the Lipschitz constants of g·d̂.",
      k["alpha"].get<double>(), k["high_alpha"].get<double>()));
  report.Table({"", "RMSE", "RMSE outside D(2)", "with payload"},
               {{"conventional", um(rmse["conventional"]), um(outside["conventional"]), Fixed(c.RmseUm(PaperCase::kConventionalPayload), 3)},
                {"DS", um(rmse["DS"]), um(outside["DS"]), Fixed(c.RmseUm(PaperCase::kDsPayload), 3)},
                {"DS, weighted", um(rmse["DS_weighted"]), um(outside["DS_weighted"]), um(rmse["DS_payload_weighted"])},
                {"PS", um(rmse["PS"]), um(outside["PS"]), Fixed(c.RmseUm(PaperCase::kPsPayload), 3)},
                {"PS, weighted", um(rmse["PS_weighted"]), um(outside["PS_weighted"]), um(rmse["PS_payload_weighted"])},
                {fmt::format("PS, weighted, α_max = {:.3g}", k["high_alpha"].get<double>()),
                 um(rmse["PS_high_alpha_weighted"]), um(outside["PS_high_alpha_weighted"]),
                 um(rmse["PS_high_alpha_payload_weighted"])}});
  std::vector<std::vector<std::string>> rows;
  auto num = [](const json& v) { return v.is_null() ? std::string("∞") : fmt::format("{:.4g}", v.get<double>()); };
  for (const char* name : {"DS", "PS", "PS_high_alpha"}) {
    const json& s = k["stability"][name];
    rows.push_back({name, num(s["alpha"]), num(s["lipschitz_x"]), num(s["lipschitz_xdot"]), num(s["rho"]),
                    num(s["alpha_max_bound"])});
  }
  report.Table({"weighted model (D2)", "α_max", "L_x of g·d̂ [N/m]", "L_ẋ of g·d̂ [N·s/m]", "ρ (DOB loop closed)",
                "α bound"},
               rows);
}

void AddAdaptiveMassFeedforward(const ReproduceContext& c, HtmlReport& report) {
  const json& a = c.online["adaptive_mass_feedforward"];
  const auto um = [](const json& v) { return Fixed(v.get<double>(), 3); };
  report.Paragraph(fmt::format(
      "diagrams/paper/gp_loop_adaptive_mass.json: gp_loop.json plus adaptive_mass_feedforward "
      "(blocks/adaptive_mass_feedforward.h), which learns the mass the nominal model lacks by recursive least squares "
      "from the DOB estimate and the measured position and scales the command by (M_n + Δm̂)/M_n (mass scheduling: "
      "the loop the PD, DOB and feedforward were designed for is restored). Estimated Δm at the end of the Fig. 9 "
      "run: {:.4f} kg with the {} kg payload, {:.4f} kg without. \"PS, smoothed\" is PS trained on the smoothed "
      "estimate (Table 2).",
      a["mass_estimate_payload_kg"].get<double>(), kPayloadMass, a["mass_estimate_no_payload_kg"].get<double>()));
  report.Table({"Fig. 9 [µm]", "no payload", "with payload", "with payload / the same GP model without payload or mass"},
               {{"conventional + adaptive mass (α = 0)", um(a["mass_only"]), um(a["mass_only_payload"]),
                 Fixed(a["mass_only_payload"].get<double>() / c.RmseUm(PaperCase::kConventional), 3)},
                {"PS + adaptive mass", um(a["PS_mass"]), um(a["PS_mass_payload"]),
                 Fixed(a["payload_over_no_payload_PS_mass"].get<double>(), 3)},
                {"PS, smoothed", um(a["PS_smoothed"]), um(a["PS_smoothed_payload"]),
                 Fixed(a["PS_smoothed_payload"].get<double>() / a["PS_smoothed"].get<double>(), 3)},
                {"PS, smoothed + adaptive mass", um(a["PS_smoothed_mass"]),
                 um(a["PS_smoothed_mass_payload"]), Fixed(a["payload_over_no_payload_PS_smoothed_mass"].get<double>(), 3)}});
}

void AddOnlineLearning(const ReproduceContext& c, HtmlReport& report) {
  const json& k = c.online;
  const json& t = k["table2"];
  const auto um = [](const json& v) { return Fixed(v.get<double>(), 3); };
  report.Heading("Learning online: the gpr block's recursive posterior (beyond the paper) [µm]");
  report.Paragraph(fmt::format(
      "diagrams/paper/gp_loop_online.json: the gpr block (learning \"online\", blocks/gpr.h) updates the posterior "
      "over its basis weights at every 1 ms step from gp_target = d̂ + d̂_g (what the DOB estimates plus what the "
      "compensation already removed), a rank-one Bayesian update with forgetting λ = {} (memory ≈ 1/(1 − λ) steps), "
      "starting from the PS model of D(2). Same Fig. 9 runs as Table 2; the payload ({} kg) is not in the training "
      "data.",
      k["forgetting"].get<double>(), kPayloadMass));
  report.Table({"", "no payload", "with payload", "payload / no payload"},
               {{"conventional", um(t["conventional"]), Fixed(c.RmseUm(PaperCase::kConventionalPayload), 3), Fixed(c.RmseUm(PaperCase::kConventionalPayload) / c.RmseUm(PaperCase::kConventional), 3)},
                {"PS (fixed)", um(t["PS"]), um(t["PS_payload"]), Fixed(t["payload_over_no_payload_fixed"].get<double>(), 3)},
                {"PS, learning online", um(t["PS_online"]), um(t["PS_online_payload"]),
                 Fixed(t["PS_online_payload"].get<double>() / t["PS_online"].get<double>(), 3)},
                {"learning online from no data (prior)", um(t["PS_online_from_prior"]), "", ""}});
  report.Paragraph(
      "The payload's force m_p·ẍ acts only while the stage accelerates and is a function of the acceleration, not "
      "of (x, ẋ): a GP on (x, ẋ) cannot hold it, offline or online — learning online does not close the payload gap "
      "on Fig. 9. An acceleration feedforward whose mass is learned online does (next table).");
  AddAdaptiveMassFeedforward(c, report);
  const json& track = k["track"];
  report.Paragraph(fmt::format(
      "A payload picked up mid-run: a forward run alternating 150 and 350 mm/s every {} s (an endless track), the "
      "payload put on at {:.1f} s. Tracking RMSE of each segment; \"from no data\" starts from the prior "
      "(learn_from \"prior\").",
      track["segment_s"].get<double>(), track["payload_time_s"].get<double>()));
  Figure f = MakeFigure("online_learning.png", "Tracking RMSE per 1.2 s segment; the payload is picked up mid-run",
                        "segment start [s]", "tracking RMSE [µm]");
  const auto starts = track["segment_start_s"].get<std::vector<double>>();
  for (const auto& [name, label] : std::vector<std::pair<std::string, std::string>>{
           {"conventional", "conventional"},
           {"PS", "PS (fixed)"},
           {"PS_online", "PS, learning online"},
           {"online_from_prior", "learning online from no data"},
           {"PS_mass", "PS + adaptive mass"},
           {"PS_smoothed", "PS, smoothed"},
           {"PS_smoothed_mass", "PS, smoothed + adaptive mass"}}) {
    f.series.push_back(MakeSeries(starts, track["segment_rmse_um"][name].get<std::vector<double>>(), label,
                                  "linespoints"));
  }
  report.AddFigure(f, c.options.out);
}

void AddRealMotor(const ReproduceContext& c, HtmlReport& report) {
  const json& m = c.real_motor;
  report.Heading("Real motor: DS and PS on an ODrive BLDC motor's cogging [A]");
  if (m.contains("skipped")) {
    report.Paragraph(m["skipped"].get<std::string>());
    return;
  }
  report.Paragraph(
      "Holding current Iq against the angle of a BLDC motor (diagrams/odrive/data, Gerry Chen's ODrive fork, "
      "MIT licence): trained on a window of the angle — D(1) a quarter, D(2) a half, D(3) three quarters of a "
      "revolution — of two slow revolutions (slow2/nocomp_0 at 0.1 rev/s, slow2_slower/nocomp_0 at 0.03 rev/s; ẋ = "
      "the record's mean speed), predicting the rest of the revolution, two other revolutions (slow2/nocomp_1, _2) "
      "and the author's quasi-static cogging map (coggingmap_0/a_16; each mean removed: the map carries no "
      "friction). PS: period 1/7 rev, and the period the fit estimates under its ±2 % prior.");
  std::vector<std::vector<std::string>> rows;
  for (const json& r : m["rows"]) {
    rows.push_back({r["kernel"].get<std::string>(), r["window"].get<std::string>(),
                    fmt::format("{:.5f}", r["period_rev"].get<double>()),
                    Fixed(r["rmse_inside_window_A"].get<double>(), 4),
                    Fixed(r["rmse_rest_of_revolution_A"].get<double>(), 4),
                    Fixed(r["rmse_other_revolutions_A"].get<double>(), 4),
                    Fixed(r["rmse_against_map_A"].get<double>(), 4),
                    Fixed(r["correlation_with_map"].get<double>(), 3)});
  }
  report.Table({"kernel", "window", "period [rev]", "inside window", "rest of revolution", "other revolutions",
                "vs map", "r with map"},
               rows);
  const json& h = m["map_harmonic_amplitudes_A"];
  report.Paragraph(fmt::format(
      "The map's harmonics [A]: 7/rev {:.3f}, 14/rev {:.3f}, 28/rev {:.3f}, 12/rev {:.3f}, 36/rev {:.3f}. A "
      "1/7-rev periodic kernel can only represent multiples of 7 per revolution: the {:.1f} % of the map's ripple "
      "power at other harmonics (12 and 36 per revolution among them: magnet or slot irregularities, not the "
      "pole-slot cogging) is a floor under PS's error that no amount of data lowers, and outside the window PS "
      "repeats the window's 12/36 content with the wrong phase. DS learns those components inside its window but "
      "forgets everything beyond it.",
      h["7"].get<double>(), h["14"].get<double>(), h["28"].get<double>(), h["12"].get<double>(),
      h["36"].get<double>(), 100.0 * m["map_power_share_not_multiple_of_7"].get<double>()));
  const auto& curves = c.real_motor_curves;
  Figure f = MakeFigure("real_motor_posterior_mean.png",
                        "Posterior mean over one revolution, trained on D(2) = [0, 0.5) rev (shaded)",
                        "angle [rev]", "Iq [A]");
  const std::vector<double>& angle = curves.at("map_angle");
  const std::vector<double>& map = curves.at("map");
  f.series.push_back(MakeSeries(angle, map, "quasi-static map (holding current)", "points"));
  for (const char* k : {"DS", "PS", "PS_estimated_period"}) f.series.push_back(MakeSeries(angle, curves.at(k), k));
  f.shaded_x_ranges = {{0.0, 0.5}};  // the training window D(2)
  report.AddFigure(f, c.options.out);
}

void AddDisturbanceFigures(const ReproduceContext& c, HtmlReport& report) {
  const ReproduceOptions& o = c.options;
  const auto& d_true = c.conv.log.Column("plant.disturbance");
  const auto& d_dob = c.conv.log.Column("dob.d_hat");
  const auto& t = c.conv.log.time;
  report.Heading("Fig. 4: disturbance along the Fig. 9 run (conventional loop)");
  {
    Figure f = MakeFigure("fig04_disturbance.png", "Disturbance along the Fig. 9 run", "time [s]", "force [N]");
    f.series.push_back(MakeSeries(t, d_true, "true disturbance d", "lines"));
    f.series.push_back(MakeSeries(t, d_dob, "DOB estimate", "lines"));
    report.AddFigure(f, o.out);
  }
  report.Heading("Fig. 5: DOB estimate against position at each scan velocity (constant-velocity sections)");
  report.Paragraph(
      "The paper draws d(x, ẋ) as a surface; the report's figures are 2-D (gnuplot lines), so the surface "
      "is shown as one curve per scan velocity: the cogging pattern repeats every 22.5 mm and its "
      "amplitude and offset change with velocity.");
  {
    Figure f =
        MakeFigure("fig05_scans.png", "DOB estimate against position, one curve per scan velocity (|x| < 100 mm)",
                   "position x [m]", "DOB estimate [N]");
    for (std::size_t s = 0; s < c.scans.size(); s += (c.scans.size() > 5 ? std::size_t{2} : std::size_t{1})) {
      std::vector<double> xs, ds;
      const auto& x = c.scans[s].Column("plant.x");
      const auto& d = c.scans[s].Column("dob.d_hat");
      const auto& flag = c.scans[s].Column("reference.constant_velocity");
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (flag[i] > 0.5 && std::abs(x[i]) < 0.1) {
          xs.push_back(x[i]);
          ds.push_back(d[i]);
        }
      }
      f.series.push_back(MakeSeries(xs, ds, fmt::format("{} m/s", c.scan_velocities[s]), "lines"));
    }
    report.AddFigure(f, o.out);
  }
}

void AddPosteriorMeanFigures(const ReproduceContext& c, HtmlReport& report) {
  const ReproduceOptions& o = c.options;
  // x from inside every window (|x| < 62.5 mm) to well outside D(3) (|x| > 162.5 mm): 15 pole pitches.
  const double fig6_min = -0.05, fig6_max = 0.3;
  report.Heading(
      "Fig. 6: posterior means at 0.35 m/s over −50 … 300 mm (windows end at 62.5, 112.5, 162.5 mm) "
      "with the D(2) training points at that velocity");
  {
    std::size_t s035 = 0;
    for (std::size_t s = 0; s < c.scan_velocities.size(); ++s) {
      if (std::abs(c.scan_velocities[s] - 0.35) < std::abs(c.scan_velocities[s035] - 0.35)) s035 = s;
    }
    const double v = c.scan_velocities[s035];
    std::vector<double> grid;
    for (int i = 0; i <= 2000; ++i) grid.push_back(fig6_min + (fig6_max - fig6_min) * i / 2000.0);
    for (int kernel = 0; kernel < 2; ++kernel) {
      Figure f =
          MakeFigure(fmt::format("fig06_{}.png", kKernelName[kernel]),
                     fmt::format("{} posterior means at {} m/s, trained on D(1), D(2), D(3)", kKernelName[kernel], v),
                     "position x [m]", "force [N]");
      {
        std::vector<double> xs, ds;
        const auto& x = c.scans[s035].Column("plant.x");
        const auto& d = c.scans[s035].Column("plant.disturbance");
        const auto& flag = c.scans[s035].Column("reference.constant_velocity");
        for (std::size_t i = 0; i < x.size(); ++i) {
          if (flag[i] > 0.5 && x[i] >= fig6_min && x[i] <= fig6_max) {
            xs.push_back(x[i]);
            ds.push_back(d[i]);
          }
        }
        f.series.push_back(MakeSeries(xs, ds, "true d (scan)", "lines"));
      }
      for (int k = 0; k < 3; ++k) {
        std::vector<double> mu;
        for (double x : grid) mu.push_back(c.ModelOf(kernel, k, false).PredictPosteriorMean(x, v));
        f.series.push_back(MakeSeries(grid, mu, fmt::format("{}{} mean", kKernelName[kernel], k + 1), "lines"));
      }
      std::vector<double> px, pd;
      for (Eigen::Index i = 0; i < c.full[1].x.size(); ++i) {
        if (std::abs(c.full[1].xdot[i] - v) < 1e-6 && c.full[1].x[i] >= fig6_min) {
          px.push_back(c.full[1].x[i]);
          pd.push_back(c.full[1].d[i]);
        }
      }
      f.series.push_back(MakeSeries(px, pd, "D(2) training points (DOB estimate)", "points"));
      report.AddFigure(f, o.out);
    }
  }
}

void AddClosedLoopFigures(const ReproduceContext& c, HtmlReport& report) {
  const ReproduceOptions& o = c.options;
  const auto& t = c.conv.log.time;
  report.Heading("Figs. 10–13: tracking error, GP estimate, DOB output and control input (Fig. 9 profile)");
  {
    struct Panel {
      const char* file;
      const char* title;
      const char* ylabel;
      const char* conv_signal;
      const char* gp_signal;
      double scale;
    };
    const Panel panels[] = {{"fig10_error.png", "Tracking error", "e [µm]", "error.y", "error.y", 1e6},
                            {"fig11_gp_estimate.png", "GP estimate (after the F-gp low-pass)", "GP estimate [N]",
                             nullptr, "f_gp.d_hat_g", 1},
                            {"fig12_dob.png", "DOB output", "DOB output [N]", "dob.d_hat", "dob.d_hat", 1},
                            {"fig13_input.png", "Control input u", "u [N]", "u_c.y", "u.y", 1}};
    for (const Panel& p : panels) {
      Figure f = MakeFigure(p.file, p.title, "time [s]", p.ylabel);
      if (p.conv_signal)
        f.series.push_back(MakeSeries(t, Scaled(c.Case(PaperCase::kConventional).result.log.Column(p.conv_signal), p.scale), "conv"));
      f.series.push_back(
          MakeSeries(c.Case(PaperCase::kDs).result.log.time, Scaled(c.Case(PaperCase::kDs).result.log.Column(p.gp_signal), p.scale), "DS"));
      f.series.push_back(
          MakeSeries(c.Case(PaperCase::kPs).result.log.time, Scaled(c.Case(PaperCase::kPs).result.log.Column(p.gp_signal), p.scale), "PS"));
      report.AddFigure(f, o.out);
    }
  }
  report.Heading("Figs. 14–17: with and without the payload (DS and PS)");
  {
    const std::pair<const char*, const char*> panels[] = {{"error.y", "Tracking error [µm]"},
                                                          {"f_gp.d_hat_g", "GP estimate [N]"},
                                                          {"dob.d_hat", "DOB output [N]"},
                                                          {"u.y", "Control input u [N]"}};
    int n = 14;
    for (const auto& [signal, label] : panels) {
      const double scale = std::string(signal) == "error.y" ? 1e6 : 1.0;
      Figure f = MakeFigure(fmt::format("fig{}_payload.png", n++), label, "time [s]", label);
      const std::pair<PaperCase, const char*> runs[] = {{PaperCase::kDs, "DS"},
                                                        {PaperCase::kPs, "PS"},
                                                        {PaperCase::kDsPayload, "DS + payload"},
                                                        {PaperCase::kPsPayload, "PS + payload"}};
      for (const auto& [which, name] : runs) {
        const SignalLog& log = c.Case(which).result.log;
        f.series.push_back(MakeSeries(log.time, Scaled(log.Column(signal), scale), name));
      }
      report.AddFigure(f, o.out);
    }
  }
}

}  // namespace

void WriteReproduceReport(ReproduceContext& c) {
  c.Say(fmt::format("[9/{}] report: results.json, report.html and figures", kSteps));
  HtmlReport report("motionblocks reproduce: TISO-GPR + DOB on the linear-motor twin");
  AddTables(c, report);
  AddConfidenceTable(c, report);
  AddOnlineLearning(c, report);
  AddRealMotor(c, report);
  AddDisturbanceFigures(c, report);
  AddPosteriorMeanFigures(c, report);
  AddClosedLoopFigures(c, report);
  c.results["timing"]["reproduce_wall_time_s"] = c.Elapsed();
  WriteJsonFile(c.results, c.options.out / "results.json");
  report.Write(c.options.out / "report.html");
}

}  // namespace mb::paper
