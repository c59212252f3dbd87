// motionblocks reproduce [--quick] [--out DIR] [--diagrams DIR] [--jobs N]
// The seed paper's experiments on the twin (tools/experiments/paper/reproduce.h): training scans, windows, DS/PS fits, Table 1,
// Table 2, the payload case, stability and the GPR's cost per step; writes DIR/results.json and DIR/report.html.

#include <iostream>

#include <fmt/format.h>

#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/experiments/paper/reproduce.h"
#include "tools/report/output_files.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

struct ReproduceCommandOptions {
  std::string out = "out/reproduce";
  std::string diagrams;  // "" = diagrams/paper of the shipped data (ShippedDataFolder)
  std::string odrive_data;
  int jobs = 0;
  bool quick = false;
};

void RunReproduceCommand(const ReproduceCommandOptions& o) {
  RequireReportFolderName("--out", o.out);
  ReproduceOptions options;
  options.out = o.out;
  options.diagrams = o.diagrams.empty() ? ShippedDataFolder() / "diagrams" / "paper" : fs::path(o.diagrams);
  options.odrive_data = o.odrive_data;
  options.jobs = o.jobs;
  options.quick = o.quick;
  options.message = [](const std::string& text) { std::cout << text << std::endl; };
  const nlohmann::json r = Reproduce(options);

  const auto& t1 = r["table1"];
  const auto& t2 = r["table2"];
  const auto& p = r["payload"];
  std::cout << "\nTable 1 — model RMSE against the true disturbance along Fig. 9 [N] (paper in brackets)\n";
  for (const char* k : {"DS", "PS"}) {
    std::cout << fmt::format("  {}  D(1) {:.4f} [{:.4f}]  D(2) {:.4f} [{:.4f}]  D(3) {:.4f} [{:.4f}]\n", k,
                             t1[k]["D1"].get<double>(), t1["paper"][k]["D1"].get<double>(), t1[k]["D2"].get<double>(),
                             t1["paper"][k]["D2"].get<double>(), t1[k]["D3"].get<double>(),
                             t1["paper"][k]["D3"].get<double>());
  }
  std::cout << fmt::format("Table 2 — tracking RMSE on Fig. 9 [µm]: conv {:.2f} [42.05]  DS {:.2f} [29.23]  PS {:.2f} "
                           "[22.41]\n",
                           t2["conventional"].get<double>(), t2["DS"].get<double>(), t2["PS"].get<double>());
  std::cout << fmt::format("Payload {} kg [µm]: conv {:.2f}  DS {:.2f}  PS {:.2f}\n", p["payload_mass_kg"].get<double>(),
                           p["conventional"].get<double>(), p["DS"].get<double>(), p["PS"].get<double>());
  std::cout << fmt::format("GPR posterior mean per control step: PS {:.0f} ns, DS {:.0f} ns (period 1 ms)\n",
                           r["timing"]["PS"]["posterior_mean_ns"].get<double>(),
                           r["timing"]["DS"]["posterior_mean_ns"].get<double>());
  std::cout << "\nFindings:\n";
  for (const auto& f : r["findings"]) std::cout << "  - " << f.get<std::string>() << "\n";
  std::cout << fmt::format("\nwrote {0}/results.json, {0}/report.html ({1:.1f} s)\n", o.out,
                           r["timing"]["reproduce_wall_time_s"].get<double>());
}

void SetupReproduceCommand(CLI::App& app) {
  auto options = std::make_shared<ReproduceCommandOptions>();
  auto* cmd = app.add_subcommand("reproduce",
                                 "Reproduce the TISO-GPR paper on the twin: scans, DS/PS fits, Table 1, Table 2, "
                                 "payload, stability, timing → results.json and report.html");
  cmd->add_flag("--quick", options->quick, "five scan velocities, one MAP start per fit (under a minute)");
  cmd->add_option("--out", options->out, "output folder")->capture_default_str();
  cmd->add_option("--diagrams", options->diagrams,
                  "folder with the paper's diagrams and sweeps/ (default: diagrams/paper of the installed data, "
                  "or of the source tree; $MOTIONBLOCKS_DATA names another data folder)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--odrive-data", options->odrive_data,
                  "ODrive cogging records for the real-motor section, a folder laid out as diagrams/odrive/data "
                  "(default: that folder, shipped)");
  cmd->add_option("--jobs,-j", options->jobs, "parallel simulations and fits (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([options] { RunReproduceCommand(*options); });
}

}  // namespace

MB_REGISTER_COMMAND(reproduce, {"reproduce", CommandGroup::kLearnedCompensation, &SetupReproduceCommand, true})

}  // namespace mb
