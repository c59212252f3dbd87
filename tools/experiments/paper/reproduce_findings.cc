// reproduce: the findings, where ours differ from the paper, stated from the numbers; results.json's tables.

#include <fmt/format.h>

#include <cmath>

#include "tools/experiments/paper/reproduce_context.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

void StateFindings(ReproduceContext& c) {
  const auto& ps1 = c.table1_ours.at("PS");
  const auto& ds1 = c.table1_ours.at("DS");
  const double conv = c.RmseUm(PaperCase::kConventional), ds = c.RmseUm(PaperCase::kDs), ps = c.RmseUm(PaperCase::kPs);
  // Findings: where ours differ from the paper, stated from the numbers.
  {
    const bool order = c.table2["order_ps_ds_conventional"].get<bool>();
    c.findings.push_back(fmt::format(
        "Table 2: conventional {:.1f} µm (paper 42.0), DS {:.1f} µm (paper 29.2), PS {:.1f} µm (paper 22.4); the "
        "ordering PS < DS < conventional {}.",
        conv, ds, ps, order ? "holds" : "does NOT hold"));
    c.findings.push_back(fmt::format(
        "The conventional figure matches by construction: the twin's disturbance and the PD/Q settings were "
        "calibrated so that conventional.json gives about 41 µm (docs/paper.md); DS and PS are predictions of this "
        "calibrated twin, not fits to Table 2. Improvement ratios: ours DS/conv {:.2f}, PS/conv {:.2f}; paper 0.70, "
        "0.53. The GP path's weight α = {:.2f} and F_gp cut-off are ours (gp_loop.json; the paper states neither); "
        "`motionblocks sweep diagrams/paper/gp_loop.json diagrams/paper/sweeps/gp_weight.json` shows the "
        "sensitivity.",
        ds / conv, ps / conv, c.stability["alpha"].get<double>()));
    const double ps_change = c.table1["ps_change_d1_to_d3_percent"].get<double>();
    c.findings.push_back(fmt::format(
        "Table 1: PS changes by {:+.1f} % from D(1) to D(3) (paper −1.5 %; required < 15 %): {}; DS {} as the "
        "window grows ({:.3f} → {:.3f} → {:.3f} N; paper 0.379 → 0.284 → 0.155).",
        ps_change, std::abs(ps_change) < 15.0 ? "holds" : "does NOT hold",
        c.table1["ds_falls_with_window"].get<bool>() ? "falls" : "does NOT fall monotonically", ds1[0], ds1[1],
        ds1[2]));
    const json& vs_dob = c.table1["against_dob_estimate"];
    c.findings.push_back(fmt::format(
        "Table 1 absolute values differ from the paper's mainly because the reference differs. Ours is the twin's "
        "true disturbance (RMS {:.3f} N along Fig. 9), which the paper cannot measure; the paper compares with its "
        "measured (DOB-estimated) disturbance. Against our DOB estimate, as the paper does, we get DS {:.3f} / {:.3f} "
        "/ {:.3f} N and PS {:.3f} / {:.3f} / {:.3f} N (paper DS 0.379 / 0.284 / 0.155, PS 0.152 / 0.151 / 0.149). "
        "The DOB estimate is Q-filtered ({:.0f} Hz) and lags the disturbance (RMSE {:.3f} N against the truth), and the "
        "GP learns that lagged, attenuated estimate (Fig. 6: PS's amplitude is below the true one): that lag, not "
        "the kernel, sets PS's floor against the truth.",
        c.d_rms, vs_dob["DS"]["D1"].get<double>(), vs_dob["DS"]["D2"].get<double>(), vs_dob["DS"]["D3"].get<double>(),
        vs_dob["PS"]["D1"].get<double>(), vs_dob["PS"]["D2"].get<double>(), vs_dob["PS"]["D3"].get<double>(),
        c.stability["PS"]["loop"]["q_cutoff_hz"].get<double>(), c.table1["dob_estimate_rmse"].get<double>()));
    c.findings.push_back(fmt::format(
        "Table 2: DS gains less than in the paper (ours ×{:.2f}, paper ×0.70) because only {:.0f} % of the Fig. 9 "
        "run (0 → 600 mm) lies inside the D(2) window (|x − x_c| ≤ 112.5 mm, x_c = {:.3f} m, the scans' centre); "
        "outside it DS reverts to its mean and the error equals the conventional one (Fig. 10), as the paper "
        "describes. The paper does not give where its windows lie relative to its test run. PS gains less than in "
        "the paper (×{:.2f} vs ×0.53) because it compensates the lagged, attenuated DOB estimate it was trained on; "
        "at 350 mm/s the cogging fundamental ({:.1f} Hz) and its harmonics sit near and above the Q cut-off "
        "({:.0f} Hz).",
        ds / conv, 100.0 * c.fraction_inside_d2, c.window_centre, ps / conv,
        0.35 / c.ModelOf(1, 1, false).hyperparameters().period,
        c.stability["PS"]["loop"]["q_cutoff_hz"].get<double>()));
    c.findings.push_back(fmt::format(
        "Ablation (only a simulation can run it): PS trained on D(2) with the true disturbance as target instead of "
        "the DOB estimate gives {:.1f} µm in Table 2 (vs {:.1f} µm; paper 22.4) and {:.3f} N in Table 1 (vs {:.3f} "
        "N): this is how much of the gap to the paper the DOB estimate's lag and attenuation explain.",
        c.RmseUm(PaperCase::kPsTrueDisturbance), ps,
        c.table1["ablation_ps_d2_trained_on_true_disturbance"].get<double>(), ps1[1]));
    c.findings.push_back(fmt::format(
        "Beyond the paper, from measured signals only: PS trained on D(2) with the smoothed estimate (the nominal "
        "inverse model M_n·ẍ + B_n·ẋ − u with a zero-phase low-pass, models/gpr/disturbance_target.h: offline "
        "training may look ahead) gives {:.1f} µm in Table 2, {:.2f} of the conventional loop (ablation on the true "
        "disturbance {:.1f} µm); with the payload {:.1f} µm.",
        c.RmseUm(PaperCase::kPsSmoothed), c.RmseUm(PaperCase::kPsSmoothed) / conv,
        c.RmseUm(PaperCase::kPsTrueDisturbance), c.RmseUm(PaperCase::kPsSmoothedPayload)));
    c.findings.push_back(fmt::format(
        "Training data: {} scans, all in the +x direction (one stroke per velocity, {} … {} m/s), sampled at 1 kHz; "
        "every sample in the window is used ({} samples in D(2) vs the paper's 2096 after downsampling); the "
        "paper-size fits give Table 1 values in results.json (table1.paper_size_fits).",
        c.scans.size(), c.scan_velocities.front(), c.scan_velocities.back(), c.full[1].x.size()));
    c.findings.push_back(fmt::format(
        "Payload: the paper adds 21 kg to a stage whose nominal mass it gives as 0.2621 (in its control-input "
        "units); we add {} kg, doubling the twin's moving mass, with M_n, B_n and the GP unchanged: conventional "
        "{:.1f} → {:.1f} µm, DS {:.1f} → {:.1f} µm, PS {:.1f} → {:.1f} µm. The paper gives no payload RMSE, only "
        "Figs. 14–17.",
        kPayloadMass, conv, c.RmseUm(PaperCase::kConventionalPayload), ds, c.RmseUm(PaperCase::kDsPayload), ps,
        c.RmseUm(PaperCase::kPsPayload)));
  }
  c.results["findings"] = c.findings;
  c.results["table1"] = c.table1;
  c.results["table2"] = c.table2;
  c.results["payload"] = c.payload_json;
  c.results["confidence_weighting"] = c.confidence;
  c.results["real_motor"] = c.real_motor;
  c.results["stability"] = c.stability;
  c.results["timing"] = c.timing;
  c.results["paper"] = {{"table1", kPaperTable1}, {"table2", kPaperTable2}};
}

}  // namespace mb::paper
