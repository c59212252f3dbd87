#include "tools/reproduce.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/diagram_loader.h"
#include "engine/file_access.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_io.h"
#include "tools/loop_from_diagram.h"
#include "tools/output_files.h"
#include "tools/report.h"
#include "tools/sweep.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// The paper's numbers (Table 1 [N], Table 2 [µm], section 3.2 dataset sizes).
const std::map<std::string, std::vector<double>> kPaperTable1 = {{"DS", {0.3789, 0.2840, 0.1550}},
                                                                 {"PS", {0.1516, 0.1506, 0.1493}}};
const std::map<std::string, double> kPaperTable2 = {{"conventional", 42.048}, {"DS", 29.228}, {"PS", 22.408}};
const int kPaperDatasetSize[3] = {1590, 2096, 2460};
const double kWindowLength[3] = {0.125, 0.225, 0.325};  // L_k of eq. 26 [m]
const char* kWindowName[3] = {"D1", "D2", "D3"};
const char* kKernelName[2] = {"DS", "PS"};
const GprKernel kKernel[2] = {GprKernel::kSeSe, GprKernel::kPeriodicSe};

using Assignments = std::vector<std::pair<std::string, json>>;

SimulationResult Simulate(const fs::path& diagram, const Assignments& assignments) {
  const json j = ApplySweepAssignments(ReadDiagramJson(diagram), assignments, diagram.string());
  const Diagram d = BuildDiagram(j, diagram.parent_path(), diagram.string());
  Simulator simulator(d);
  return simulator.Run();
}

Diagram BuildWith(const fs::path& diagram, const Assignments& assignments) {
  const json j = ApplySweepAssignments(ReadDiagramJson(diagram), assignments, diagram.string());
  return BuildDiagram(j, diagram.parent_path(), diagram.string());
}

std::vector<double> Scaled(const std::vector<double>& v, double k) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [k](double a) { return k * a; });
  return out;
}

// Posterior mean along a log's position and velocity columns.
std::vector<double> PredictAlong(const GprModel& model, const SignalLog& log, const std::string& position,
                                 const std::string& velocity) {
  const auto& x = log.Column(position);
  const auto& v = log.Column(velocity);
  std::vector<double> mu(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) mu[i] = model.PredictPosteriorMean(x[i], v[i]);
  return mu;
}

Figure MakeFigure(std::string file, std::string title, std::string xlabel, std::string ylabel) {
  Figure f;
  f.file = std::move(file);
  f.title = std::move(title);
  f.xlabel = std::move(xlabel);
  f.ylabel = std::move(ylabel);
  return f;
}

Series MakeSeries(std::vector<double> x, std::vector<double> y, std::string label, std::string style = "lines") {
  Series s;
  s.x = std::move(x);
  s.y = std::move(y);
  s.label = std::move(label);
  s.style = std::move(style);
  return s;
}

std::string Fixed(double v, int digits) { return fmt::format("{:.{}f}", v, digits); }

std::string Percent(double ours, double paper) { return fmt::format("{:+.1f} %", 100.0 * (ours - paper) / paper); }

}  // namespace

GprTrainingSet SelectTrainingWindow(const std::vector<SignalLog>& scans, double window_length, int downsample,
                                    const std::string& target) {
  if (!(window_length > 0.0)) {
    throw std::invalid_argument(fmt::format("training window length must be positive, got {} m", window_length));
  }
  if (downsample < 1) throw std::invalid_argument(fmt::format("downsample must be ≥ 1, got {}", downsample));
  std::vector<double> xs, vs, ds;
  long long kept = 0;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    const auto& x = scans[s].Column("plant.x");
    const auto& v = scans[s].Column("reference.velocity");
    const auto& d = scans[s].Column(target);
    const auto& flag = scans[s].Column("reference.constant_velocity");
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (flag[i] > 0.5) {
        lo = std::min(lo, x[i]);
        hi = std::max(hi, x[i]);
      }
    }
    if (!(lo <= hi)) throw std::invalid_argument(fmt::format("scan {} has no constant-velocity section", s));
    const double centre = 0.5 * (lo + hi);  // x_c,i of eq. 25
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (flag[i] > 0.5 && std::abs(x[i] - centre) <= 0.5 * window_length) {
        if (kept++ % downsample == 0) {
          xs.push_back(x[i]);
          vs.push_back(v[i]);
          ds.push_back(d[i]);
        }
      }
    }
  }
  GprTrainingSet set;
  set.x = Eigen::Map<const Eigen::VectorXd>(xs.data(), static_cast<Eigen::Index>(xs.size()));
  set.xdot = Eigen::Map<const Eigen::VectorXd>(vs.data(), static_cast<Eigen::Index>(vs.size()));
  set.d = Eigen::Map<const Eigen::VectorXd>(ds.data(), static_cast<Eigen::Index>(ds.size()));
  return set;
}

double RootMeanSquareDifference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.empty()) {
    throw std::invalid_argument(fmt::format("RMS difference of {} and {} samples", a.size(), b.size()));
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

json Reproduce(const ReproduceOptions& o) {
  const auto t_start = std::chrono::steady_clock::now();
  const int jobs = o.jobs > 0 ? o.jobs : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  tbb::task_arena arena(jobs);
  auto say = [&](const std::string& text) {
    if (o.message) o.message(text);
  };
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(); };
  const int steps = 9;

  const fs::path conventional = o.diagrams / "conventional.json";
  const fs::path gp_loop = o.diagrams / "gp_loop.json";
  const fs::path training_scan = o.diagrams / "training_scan.json";
  const fs::path scans_sweep = o.diagrams / "sweeps" / "training_scans.json";
  fs::create_directories(o.out / "models");
  AllowDiagramFilesUnder(o.out / "models");  // the paper's diagrams read the GP models this run writes there
  json results;
  results["configuration"] = {{"quick", o.quick},
                              {"jobs", jobs},
                              {"diagrams", fs::absolute(o.diagrams).string()},
                              {"window_lengths_m", {kWindowLength[0], kWindowLength[1], kWindowLength[2]}}};

  // 1. Training scans (section 3.2): the list sweep, in parallel; logs kept in memory.
  SweepSpec scan_spec = ReadSweepFile(scans_sweep);
  if (o.quick) {
    std::vector<SweepRun> every_other;
    for (std::size_t i = 0; i < scan_spec.runs.size(); i += 2) every_other.push_back(scan_spec.runs[i]);
    scan_spec.runs = every_other;
  }
  say(fmt::format("[1/{}] training scans: {} constant-velocity strokes over 700 mm ({})", steps,
                  scan_spec.runs.size(), scans_sweep.string()));
  std::vector<SignalLog> scans(scan_spec.runs.size());
  std::vector<double> scan_velocities;
  for (const auto& run : scan_spec.runs) {
    for (const auto& [k, v] : run.assignments) {
      if (k == "reference.velocities") scan_velocities.push_back(v.at(0).get<double>());
    }
  }
  {
    SweepOptions so;
    so.jobs = jobs;
    so.resume = false;
    so.progress = o.progress;
    so.on_result = [&](std::size_t i, const SimulationResult& r) { scans[i] = r.log; };
    const SweepOutcome outcome = RunSweep(training_scan, scan_spec, o.out / "scans", so);
    for (const auto& row : outcome.rows) {
      if (row.status != "ok") throw std::runtime_error(fmt::format("training scan {} failed: {}", row.id, row.error));
    }
  }
  results["configuration"]["scan_velocities_m_s"] = scan_velocities;

  // 2. Windows D(1..3) (eq. 25–26), every sample and a paper-size downsample.
  say(fmt::format("[2/{}] training windows D(1), D(2), D(3): L = 125, 225, 325 mm around each scan's centre", steps));
  GprTrainingSet full[3], paper_size[3];
  json datasets;
  for (int k = 0; k < 3; ++k) {
    full[k] = SelectTrainingWindow(scans, kWindowLength[k]);
    const int factor = std::max(1, static_cast<int>(std::lround(static_cast<double>(full[k].x.size()) /
                                                                 kPaperDatasetSize[k])));
    paper_size[k] = SelectTrainingWindow(scans, kWindowLength[k], factor);
    datasets[kWindowName[k]] = {{"window_m", kWindowLength[k]},
                                {"samples", full[k].x.size()},
                                {"paper_size_downsample", factor},
                                {"paper_size_samples", paper_size[k].x.size()},
                                {"paper_samples", kPaperDatasetSize[k]}};
  }
  results["configuration"]["datasets"] = datasets;

  // 3. MAP fits: {DS, PS} × {D1, D2, D3} × {every sample, paper-size}.
  struct Fit {
    int kernel;
    int window;
    bool paper_size;
    std::unique_ptr<GprModel> model;
    double seconds = 0.0;
  };
  std::vector<Fit> fits;
  for (int paper = 0; paper < 2; ++paper) {
    for (int kernel = 0; kernel < 2; ++kernel) {
      for (int k = 0; k < 3; ++k) fits.push_back(Fit{kernel, k, paper == 1, nullptr, 0.0});
    }
  }
  say(fmt::format("[3/{}] MAP fits of DS and PS on D(1..3): {} models (every sample, and paper-size for the record)",
                  steps, fits.size()));
  {
    ProgressLine progress("fits");
    std::mutex mutex;
    int done = 0;
    arena.execute([&] {
      tbb::parallel_for(std::size_t{0}, fits.size(), [&](std::size_t i) {
        Fit& f = fits[i];
        const GprTrainingSet& data = f.paper_size ? paper_size[f.window] : full[f.window];
        GprFitOptions fo;
        fo.kernel = kKernel[f.kernel];
        fo.restarts = o.quick ? 0 : 2;
        fo.source = fmt::format("motionblocks reproduce: {} window L = {} mm, {} scans{}", kWindowName[f.window],
                                kWindowLength[f.window] * 1e3, scans.size(), f.paper_size ? ", paper-size" : "");
        const auto t0 = std::chrono::steady_clock::now();
        f.model = std::make_unique<GprModel>(FitGpr(data.x, data.xdot, data.d, fo));
        f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::lock_guard<std::mutex> lock(mutex);
        ++done;
        if (o.progress) progress.Update(static_cast<double>(done) / static_cast<double>(fits.size()));
      });
    });
    if (o.progress) progress.Done();
  }
  auto model_of = [&](int kernel, int window, bool paper) -> const GprModel& {
    for (const auto& f : fits) {
      if (f.kernel == kernel && f.window == window && f.paper_size == paper) return *f.model;
    }
    throw std::logic_error("missing fit");
  };
  std::map<std::string, fs::path> model_paths;
  json models_json;
  for (const auto& f : fits) {
    const std::string name = fmt::format("{}_{}{}", kKernelName[f.kernel], kWindowName[f.window],
                                         f.paper_size ? "_paper_size" : "");
    fs::path path = o.out / "models" / (name + ".json");
    SaveGprModel(*f.model, path);
    model_paths[name] = fs::absolute(path);
    const auto& h = f.model->hyperparameters();
    models_json[name] = {{"file", path.string()},
                         {"samples", f.model->data().provenance.sample_count},
                         {"features", f.model->feature_count()},
                         {"fit_seconds", f.seconds},
                         {"signal_variance_x", h.signal_variance_x},
                         {"length_scale_x", h.length_scale_x},
                         {"signal_variance_xdot", h.signal_variance_xdot},
                         {"length_scale_xdot", h.length_scale_xdot},
                         {"noise_variance", h.noise_variance}};
  }
  results["models"] = models_json;

  // Ablation (simulation only): PS on D(2) trained on the true disturbance instead of the DOB estimate.
  const GprTrainingSet true_target = SelectTrainingWindow(scans, kWindowLength[1], 1, "plant.disturbance");
  GprFitOptions ablation_options;
  ablation_options.kernel = GprKernel::kPeriodicSe;
  ablation_options.restarts = o.quick ? 0 : 2;
  ablation_options.source = "motionblocks reproduce: ablation, D2 window, target = true disturbance";
  const GprModel ps_true_target = FitGpr(true_target.x, true_target.xdot, true_target.d, ablation_options);
  const fs::path ps_true_target_path = fs::absolute(o.out / "models" / "PS_D2_true_disturbance.json");
  SaveGprModel(ps_true_target, ps_true_target_path);

  // 4. Table 1 along the Fig. 9 run of the conventional loop.
  say(fmt::format("[4/{}] Table 1: model RMSE against the disturbance along the Fig. 9 run (0 … 600 mm)", steps));
  const SimulationResult conv = Simulate(conventional, {});
  const auto& d_true = conv.log.Column("plant.disturbance");
  const auto& d_dob = conv.log.Column("dob.d_hat");
  json table1;
  table1["unit"] = "N";
  table1["reference"] = "the twin's true disturbance plant.disturbance along the Fig. 9 run of conventional.json";
  std::map<std::string, std::vector<double>> table1_ours;
  for (int kernel = 0; kernel < 2; ++kernel) {
    std::vector<double> rmse, rmse_dob, rmse_paper_size;
    for (int k = 0; k < 3; ++k) {
      const auto mu = PredictAlong(model_of(kernel, k, false), conv.log, "plant.x", "plant.velocity");
      rmse.push_back(RootMeanSquareDifference(mu, d_true));
      rmse_dob.push_back(RootMeanSquareDifference(mu, d_dob));
      const auto mu_p = PredictAlong(model_of(kernel, k, true), conv.log, "plant.x", "plant.velocity");
      rmse_paper_size.push_back(RootMeanSquareDifference(mu_p, d_true));
    }
    table1_ours[kKernelName[kernel]] = rmse;
    table1[kKernelName[kernel]] = {{"D1", rmse[0]}, {"D2", rmse[1]}, {"D3", rmse[2]}};
    table1["against_dob_estimate"][kKernelName[kernel]] = {
        {"D1", rmse_dob[0]}, {"D2", rmse_dob[1]}, {"D3", rmse_dob[2]}};
    table1["paper_size_fits"][kKernelName[kernel]] = {
        {"D1", rmse_paper_size[0]}, {"D2", rmse_paper_size[1]}, {"D3", rmse_paper_size[2]}};
    table1["paper"][kKernelName[kernel]] = {{"D1", kPaperTable1.at(kKernelName[kernel])[0]},
                                            {"D2", kPaperTable1.at(kKernelName[kernel])[1]},
                                            {"D3", kPaperTable1.at(kKernelName[kernel])[2]}};
  }
  const double d_rms = RootMeanSquareDifference(d_true, std::vector<double>(d_true.size(), 0.0));
  table1["ablation_ps_d2_trained_on_true_disturbance"] =
      RootMeanSquareDifference(PredictAlong(ps_true_target, conv.log, "plant.x", "plant.velocity"), d_true);
  // Where the Fig. 9 run lies relative to the D(2) window (its centre: the mean of the scans' centres).
  const double window_centre = full[1].x.size() > 0 ? 0.5 * (full[1].x.minCoeff() + full[1].x.maxCoeff()) : 0.0;
  double fraction_inside_d2 = 0.0;
  {
    const auto& x = conv.log.Column("plant.x");
    long long inside = 0;
    for (double xi : x) inside += std::abs(xi - window_centre) <= 0.5 * kWindowLength[1] ? 1 : 0;
    fraction_inside_d2 = static_cast<double>(inside) / static_cast<double>(x.size());
  }
  table1["fig9_fraction_inside_D2"] = fraction_inside_d2;
  table1["disturbance_rms"] = d_rms;
  table1["dob_estimate_rmse"] = RootMeanSquareDifference(d_dob, d_true);
  const auto& ps1 = table1_ours["PS"];
  const auto& ds1 = table1_ours["DS"];
  table1["ps_change_d1_to_d3_percent"] = 100.0 * (ps1[2] - ps1[0]) / ps1[0];
  table1["ds_falls_with_window"] = ds1[0] > ds1[1] && ds1[1] > ds1[2];

  // 5–6. Table 2 and the payload case: six closed-loop runs in parallel.
  const double payload = 0.2621;  // = M: doubles the moving mass (docs/paper.md on the paper's 21 kg)
  struct Case {
    std::string name;
    fs::path diagram;
    Assignments assignments;
    SimulationResult result;
  };
  std::vector<Case> cases = {
      {"conventional", conventional, {}, {}},
      {"DS", gp_loop, {{"gpr.model", model_paths["DS_D2"].string()}}, {}},
      {"PS", gp_loop, {{"gpr.model", model_paths["PS_D2"].string()}}, {}},
      {"conventional_payload", conventional, {{"plant.payload_mass", payload}}, {}},
      {"DS_payload", gp_loop, {{"gpr.model", model_paths["DS_D2"].string()}, {"plant.payload_mass", payload}}, {}},
      {"PS_payload", gp_loop, {{"gpr.model", model_paths["PS_D2"].string()}, {"plant.payload_mass", payload}}, {}},
      {"PS_true_disturbance", gp_loop, {{"gpr.model", ps_true_target_path.string()}}, {}}};
  say(fmt::format("[5/{}] Table 2 and section 5.3: Fig. 9 runs, conventional / DS / PS (D(2)), without and with a "
                  "{} kg payload",
                  steps, payload));
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, cases.size(),
                      [&](std::size_t i) { cases[i].result = Simulate(cases[i].diagram, cases[i].assignments); });
  });
  auto rmse_um = [&](std::size_t i) { return cases[i].result.metrics.at("tracking_rmse") * 1e6; };
  json table2 = {{"unit", "µm"},
                 {"conventional", rmse_um(0)},
                 {"DS", rmse_um(1)},
                 {"PS", rmse_um(2)},
                 {"max_abs_um",
                  {{"conventional", cases[0].result.metrics.at("tracking_max_abs") * 1e6},
                   {"DS", cases[1].result.metrics.at("tracking_max_abs") * 1e6},
                   {"PS", cases[2].result.metrics.at("tracking_max_abs") * 1e6}}},
                 {"paper", kPaperTable2},
                 {"order_ps_ds_conventional", rmse_um(2) < rmse_um(1) && rmse_um(1) < rmse_um(0)},
                 {"ablation_ps_trained_on_true_disturbance", rmse_um(6)}};
  json payload_json = {{"unit", "µm"},
                       {"payload_mass_kg", payload},
                       {"moving_mass_kg", 0.2621},
                       {"conventional", rmse_um(3)},
                       {"DS", rmse_um(4)},
                       {"PS", rmse_um(5)},
                       {"without_payload", {{"conventional", rmse_um(0)}, {"DS", rmse_um(1)}, {"PS", rmse_um(2)}}}};

  // The payload study as sweeps (diagrams/paper/sweeps): conventional.json and gp_loop.json with each D(2) model.
  say(fmt::format("[6/{}] payload study: sweeps/payload_conventional.json and sweeps/payload_gp_loop.json (DS, PS)",
                  steps));
  {
    struct PayloadSweep {
      const char* name;
      fs::path diagram;
      fs::path sweep;
      std::string model;
    };
    const PayloadSweep sweeps[] = {
        {"conventional", conventional, o.diagrams / "sweeps" / "payload_conventional.json", ""},
        {"DS", gp_loop, o.diagrams / "sweeps" / "payload_gp_loop.json", model_paths["DS_D2"].string()},
        {"PS", gp_loop, o.diagrams / "sweeps" / "payload_gp_loop.json", model_paths["PS_D2"].string()}};
    json study;
    for (const PayloadSweep& ps : sweeps) {
      SweepSpec spec = ReadSweepFile(ps.sweep);
      if (!ps.model.empty()) spec.fixed.emplace_back("gpr.model", ps.model);
      SweepOptions so;
      so.jobs = jobs;
      so.resume = false;
      so.progress = o.progress;
      const SweepOutcome outcome = RunSweep(ps.diagram, spec, o.out / "payload_study" / ps.name, so);
      std::vector<double> mass, rmse;
      for (const SweepRow& row : outcome.rows) {
        if (row.status != "ok") {
          throw std::runtime_error(fmt::format("payload sweep {} run {} failed: {}", ps.name, row.id, row.error));
        }
        for (const auto& [k, v] : row.assignments) {
          if (k == "plant.payload_mass") mass.push_back(v.get<double>());
        }
        rmse.push_back(row.metrics.at("tracking_rmse") * 1e6);
      }
      study["payload_mass_kg"] = mass;
      study[ps.name] = rmse;
    }
    study["unit"] = "µm";
    payload_json["sweep"] = study;
  }

  // 7. Stability for the α of gp_loop.json, with each D(2) model.
  say(fmt::format("[7/{}] stability (section 4.2): ρ and the α bound for the gp_loop's α with the DS and PS models",
                  steps));
  json stability;
  for (int kernel = 0; kernel < 2; ++kernel) {
    const Diagram d = BuildWith(gp_loop, {{"gpr.model", model_paths[fmt::format("{}_D2", kKernelName[kernel])].string()}});
    const StabilityReport report = AnalyseStability(d, &model_of(kernel, 1, false));
    json j = ToJson(report);
    j.erase("bode");
    stability[kKernelName[kernel]] = j;
    stability["alpha"] = report.loop.gp_weight;
  }

  // 8. The GPR's cost per control step: the posterior mean as the gpr block evaluates it (O(M), no allocation).
  say(fmt::format("[8/{}] timing: GPR posterior mean per control step", steps));
  json timing;
  {
    const int calls = o.quick ? 200000 : 2000000;
    const auto& xs = conv.log.Column("plant.x");
    const auto& vs = conv.log.Column("plant.velocity");
    for (int kernel = 0; kernel < 2; ++kernel) {
      const GprModel& m = model_of(kernel, 1, false);
      volatile double sink = 0.0;
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < calls; ++i) {
        const std::size_t j = static_cast<std::size_t>(i) % xs.size();
        sink = sink + m.PredictPosteriorMean(xs[j], vs[j]);
      }
      const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() /
                        static_cast<double>(calls);
      double mean_std_ns = 0.0;
      {
        const int n = calls / 10;
        const auto t1 = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) {
          const std::size_t j = static_cast<std::size_t>(i) % xs.size();
          double mean = 0.0, sd = 0.0;
          m.Predict(xs[j], vs[j], &mean, &sd);
          sink = sink + mean + sd;
        }
        mean_std_ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t1).count() /
                      static_cast<double>(n);
      }
      timing[kKernelName[kernel]] = {{"posterior_mean_ns", ns},
                                     {"mean_and_std_ns", mean_std_ns},
                                     {"features", m.feature_count()},
                                     {"training_samples", m.data().provenance.sample_count},
                                     {"fraction_of_control_period", ns * 1e-9 / 1e-3}};
    }
    const double steps_conv = static_cast<double>(cases[0].result.solver_stats.steps);
    timing["control_period_s"] = 1e-3;
    timing["simulation_wall_time_s"] = {{"conventional", cases[0].result.wall_time_s},
                                        {"DS", cases[1].result.wall_time_s},
                                        {"PS", cases[2].result.wall_time_s},
                                        {"solver_steps", steps_conv}};
    json fit_seconds;
    for (const auto& f : fits) {
      fit_seconds[fmt::format("{}_{}{}", kKernelName[f.kernel], kWindowName[f.window],
                              f.paper_size ? "_paper_size" : "")] = f.seconds;
    }
    timing["fit_seconds"] = fit_seconds;
    timing["paper_note"] =
        "the paper gives no per-step figure for its exact GP beyond 'executed at each control sampling time in real "
        "time' at 1 ms (section 5.1); ours is the weight-space posterior mean, independent of N";
  }

  // Findings: where ours differ from the paper, stated from the numbers.
  std::vector<std::string> findings;
  {
    const bool order = table2["order_ps_ds_conventional"].get<bool>();
    findings.push_back(fmt::format(
        "Table 2: conventional {:.1f} µm (paper 42.0), DS {:.1f} µm (paper 29.2), PS {:.1f} µm (paper 22.4); the "
        "ordering PS < DS < conventional {}.",
        rmse_um(0), rmse_um(1), rmse_um(2), order ? "holds" : "does NOT hold"));
    findings.push_back(fmt::format(
        "The conventional figure matches by construction: the twin's disturbance and the PD/Q settings were "
        "calibrated so that conventional.json gives about 41 µm (docs/paper.md); DS and PS are predictions of this "
        "calibrated twin, not fits to Table 2. Improvement ratios: ours DS/conv {:.2f}, PS/conv {:.2f}; paper 0.70, "
        "0.53. The GP path's weight α = {:.2f} and F_gp cut-off are ours (gp_loop.json; the paper states neither); "
        "`motionblocks sweep diagrams/paper/gp_loop.json diagrams/paper/sweeps/gp_weight.json` shows the "
        "sensitivity.",
        rmse_um(1) / rmse_um(0), rmse_um(2) / rmse_um(0), stability["alpha"].get<double>()));
    const double ps_change = table1["ps_change_d1_to_d3_percent"].get<double>();
    findings.push_back(fmt::format(
        "Table 1: PS changes by {:+.1f} % from D(1) to D(3) (paper −1.5 %; required < 15 %): {}; DS {} as the "
        "window grows ({:.3f} → {:.3f} → {:.3f} N; paper 0.379 → 0.284 → 0.155).",
        ps_change, std::abs(ps_change) < 15.0 ? "holds" : "does NOT hold",
        table1["ds_falls_with_window"].get<bool>() ? "falls" : "does NOT fall monotonically", ds1[0], ds1[1],
        ds1[2]));
    const json& vs_dob = table1["against_dob_estimate"];
    findings.push_back(fmt::format(
        "Table 1 absolute values differ from the paper's mainly because the reference differs. Ours is the twin's "
        "true disturbance (RMS {:.3f} N along Fig. 9), which the paper cannot measure; the paper compares with its "
        "measured (DOB-estimated) disturbance. Against our DOB estimate, as the paper does, we get DS {:.3f} / {:.3f} "
        "/ {:.3f} N and PS {:.3f} / {:.3f} / {:.3f} N (paper DS 0.379 / 0.284 / 0.155, PS 0.152 / 0.151 / 0.149). "
        "The DOB estimate is Q-filtered ({:.0f} Hz) and lags the disturbance (RMSE {:.3f} N against the truth), and the "
        "GP learns that lagged, attenuated estimate (Fig. 6: PS's amplitude is below the true one): that lag, not "
        "the kernel, sets PS's floor against the truth.",
        d_rms, vs_dob["DS"]["D1"].get<double>(), vs_dob["DS"]["D2"].get<double>(), vs_dob["DS"]["D3"].get<double>(),
        vs_dob["PS"]["D1"].get<double>(), vs_dob["PS"]["D2"].get<double>(), vs_dob["PS"]["D3"].get<double>(),
        stability["PS"]["loop"]["q_cutoff_hz"].get<double>(), table1["dob_estimate_rmse"].get<double>()));
    findings.push_back(fmt::format(
        "Table 2: DS gains less than in the paper (ours ×{:.2f}, paper ×0.70) because only {:.0f} % of the Fig. 9 "
        "run (0 → 600 mm) lies inside the D(2) window (|x − x_c| ≤ 112.5 mm, x_c = {:.3f} m, the scans' centre); "
        "outside it DS reverts to its mean and the error equals the conventional one (Fig. 10), as the paper "
        "describes. The paper does not give where its windows lie relative to its test run. PS gains less than in "
        "the paper (×{:.2f} vs ×0.53) because it compensates the lagged, attenuated DOB estimate it was trained on; "
        "at 350 mm/s the cogging fundamental ({:.1f} Hz) and its harmonics sit near and above the Q cut-off "
        "({:.0f} Hz).",
        rmse_um(1) / rmse_um(0), 100.0 * fraction_inside_d2, window_centre, rmse_um(2) / rmse_um(0),
        0.35 / model_of(1, 1, false).hyperparameters().period, stability["PS"]["loop"]["q_cutoff_hz"].get<double>()));
    findings.push_back(fmt::format(
        "Ablation (only a simulation can run it): PS trained on D(2) with the true disturbance as target instead of "
        "the DOB estimate gives {:.1f} µm in Table 2 (vs {:.1f} µm; paper 22.4) and {:.3f} N in Table 1 (vs {:.3f} "
        "N): this is how much of the gap to the paper the DOB estimate's lag and attenuation explain.",
        rmse_um(6), rmse_um(2), table1["ablation_ps_d2_trained_on_true_disturbance"].get<double>(), ps1[1]));
    findings.push_back(fmt::format(
        "Training data: {} scans, all in the +x direction (one stroke per velocity, {} … {} m/s), sampled at 1 kHz; "
        "every sample in the window is used ({} samples in D(2) vs the paper's 2096 after downsampling); the "
        "paper-size fits give Table 1 values in results.json (table1.paper_size_fits).",
        scans.size(), scan_velocities.front(), scan_velocities.back(), full[1].x.size()));
    findings.push_back(fmt::format(
        "Payload: the paper adds 21 kg to a stage whose nominal mass it gives as 0.2621 (in its control-input "
        "units); we add {} kg, doubling the twin's moving mass, with M_n, B_n and the GP unchanged: conventional "
        "{:.1f} → {:.1f} µm, DS {:.1f} → {:.1f} µm, PS {:.1f} → {:.1f} µm. The paper gives no payload RMSE, only "
        "Figs. 14–17.",
        payload, rmse_um(0), rmse_um(3), rmse_um(1), rmse_um(4), rmse_um(2), rmse_um(5)));
  }
  results["findings"] = findings;
  results["table1"] = table1;
  results["table2"] = table2;
  results["payload"] = payload_json;
  results["stability"] = stability;
  results["timing"] = timing;
  results["paper"] = {{"table1", kPaperTable1}, {"table2", kPaperTable2}};

  // Report.
  say(fmt::format("[9/{}] report: results.json, report.html and figures", steps));
  HtmlReport report("motionblocks reproduce: TISO-GPR + DOB on the linear-motor twin");
  report.Paragraph(fmt::format(
      "Reproduction of Jung et al., TISO-GPR integrated with disturbance observers (reference/paper-tisogpr-dob.txt), "
      "on the simulated linear-motor twin (docs/paper.md), from diagrams/paper/ ({} mode: {} scan velocities, {} "
      "MAP start(s) per fit; {} threads, {:.1f} s).",
      o.quick ? "quick" : "full", scans.size(), o.quick ? 1 : 3, jobs, elapsed()));
  report.Heading("Where our figures differ from the paper's, and why");
  for (const auto& f : findings) report.Paragraph(f);

  report.Heading("Table 1: model RMSE over the full operating range [N]");
  {
    std::vector<std::vector<std::string>> rows;
    for (int kernel = 0; kernel < 2; ++kernel) {
      const std::string kname = kKernelName[kernel];
      std::vector<std::string> row = {kname + " (ours, vs true d)"};
      for (int k = 0; k < 3; ++k) row.push_back(Fixed(table1_ours[kname][static_cast<std::size_t>(k)], 4));
      rows.push_back(row);
      row = {kname + " (ours, vs DOB estimate)"};
      for (int k = 0; k < 3; ++k) row.push_back(Fixed(table1["against_dob_estimate"][kname][kWindowName[k]].get<double>(), 4));
      rows.push_back(row);
      row = {kname + " (ours, paper-size N, vs true d)"};
      for (int k = 0; k < 3; ++k) row.push_back(Fixed(table1["paper_size_fits"][kname][kWindowName[k]].get<double>(), 4));
      rows.push_back(row);
      row = {kname + " (paper)"};
      for (int k = 0; k < 3; ++k) row.push_back(Fixed(kPaperTable1.at(kname)[static_cast<std::size_t>(k)], 4));
      rows.push_back(row);
    }
    report.Table({"kernel", "D(1) 125 mm", "D(2) 225 mm", "D(3) 325 mm"}, rows);
    std::vector<std::vector<std::string>> sizes;
    for (int k = 0; k < 3; ++k) {
      sizes.push_back({kWindowName[k], fmt::format("{}", full[k].x.size()), fmt::format("{}", paper_size[k].x.size()),
                       fmt::format("{}", kPaperDatasetSize[k])});
    }
    report.Table({"window", "samples (ours, all)", "paper-size downsample", "paper"}, sizes);
  }
  report.Heading("Table 2: tracking RMSE on the Fig. 9 profile [µm]");
  report.Table({"", "conv", "DS", "PS"},
               {{"ours", Fixed(rmse_um(0), 3), Fixed(rmse_um(1), 3), Fixed(rmse_um(2), 3)},
                {"paper", "42.048", "29.228", "22.408"},
                {"difference", Percent(rmse_um(0), 42.048), Percent(rmse_um(1), 29.228), Percent(rmse_um(2), 22.408)},
                {"ablation: PS trained on the true d", "", "", Fixed(rmse_um(6), 3)}});
  report.Heading(fmt::format("Section 5.3: payload {} kg (moving mass doubled), models not retrained [µm]", payload));
  report.Table({"", "conv", "DS", "PS"},
               {{"without payload", Fixed(rmse_um(0), 3), Fixed(rmse_um(1), 3), Fixed(rmse_um(2), 3)},
                {"with payload", Fixed(rmse_um(3), 3), Fixed(rmse_um(4), 3), Fixed(rmse_um(5), 3)}});
  {
    const json& study = payload_json["sweep"];
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
      const json& s = stability[kKernelName[kernel]];
      auto num = [](const json& v) { return v.is_null() ? std::string("∞") : fmt::format("{:.4g}", v.get<double>()); };
      rows.push_back({kKernelName[kernel], fmt::format("{:.3g}", stability["alpha"].get<double>()),
                      num(s["dob"]["lipschitz_x"]), num(s["dob"]["lipschitz_xdot"]), num(s["dob"]["rho"]),
                      num(s["dob"]["alpha_max_bound"]), num(s["paper"]["rho"]),
                      fmt::format("{:.0f}", timing[kKernelName[kernel]]["posterior_mean_ns"].get<double>()),
                      fmt::format("{}", timing[kKernelName[kernel]]["features"].get<int>())});
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

  // Figures.
  const auto& t = conv.log.time;
  report.Heading("Fig. 4: disturbance along the Fig. 9 run (conventional loop)");
  {
    Figure f = MakeFigure("fig04_disturbance.png", "Disturbance along the Fig. 9 run", "time [s]", "force [N]");
    f.series.push_back(MakeSeries(t, d_true, "true disturbance d", "lines"));
    f.series.push_back(MakeSeries(t, d_dob, "DOB estimate", "lines"));
    report.AddFigure(f, o.out);
  }
  report.Heading("Fig. 5: DOB estimate against position at each scan velocity (constant-velocity sections)");
  report.Paragraph("The paper draws d(x, ẋ) as a surface; the report's figures are 2-D (gnuplot lines), so the surface "
                   "is shown as one curve per scan velocity: the cogging pattern repeats every 22.5 mm and its "
                   "amplitude and offset change with velocity.");
  {
    Figure f = MakeFigure("fig05_scans.png", "DOB estimate against position, one curve per scan velocity (|x| < 100 mm)", "position x [m]", "DOB estimate [N]");
    for (std::size_t s = 0; s < scans.size(); s += (scans.size() > 5 ? std::size_t{2} : std::size_t{1})) {
      std::vector<double> xs, ds;
      const auto& x = scans[s].Column("plant.x");
      const auto& d = scans[s].Column("dob.d_hat");
      const auto& flag = scans[s].Column("reference.constant_velocity");
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (flag[i] > 0.5 && std::abs(x[i]) < 0.1) {
          xs.push_back(x[i]);
          ds.push_back(d[i]);
        }
      }
      f.series.push_back(MakeSeries(xs, ds, fmt::format("{} m/s", scan_velocities[s]), "lines"));
    }
    report.AddFigure(f, o.out);
  }
  // x from inside every window (|x| < 62.5 mm) to well outside D(3) (|x| > 162.5 mm): 15 pole pitches.
  const double fig6_min = -0.05, fig6_max = 0.3;
  report.Heading("Fig. 6: posterior means at 0.35 m/s over −50 … 300 mm (windows end at 62.5, 112.5, 162.5 mm) "
                 "with the D(2) training points at that velocity");
  {
    std::size_t s035 = 0;
    for (std::size_t s = 0; s < scan_velocities.size(); ++s) {
      if (std::abs(scan_velocities[s] - 0.35) < std::abs(scan_velocities[s035] - 0.35)) s035 = s;
    }
    const double v = scan_velocities[s035];
    std::vector<double> grid;
    for (int i = 0; i <= 2000; ++i) grid.push_back(fig6_min + (fig6_max - fig6_min) * i / 2000.0);
    for (int kernel = 0; kernel < 2; ++kernel) {
      Figure f = MakeFigure(fmt::format("fig06_{}.png", kKernelName[kernel]),
               fmt::format("{} posterior means at {} m/s, trained on D(1), D(2), D(3)", kKernelName[kernel], v),
                            "position x [m]", "force [N]");
      {
        std::vector<double> xs, ds;
        const auto& x = scans[s035].Column("plant.x");
        const auto& d = scans[s035].Column("plant.disturbance");
        const auto& flag = scans[s035].Column("reference.constant_velocity");
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
        for (double x : grid) mu.push_back(model_of(kernel, k, false).PredictPosteriorMean(x, v));
        f.series.push_back(MakeSeries(grid, mu, fmt::format("{}{} mean", kKernelName[kernel], k + 1), "lines"));
      }
      std::vector<double> px, pd;
      for (Eigen::Index i = 0; i < full[1].x.size(); ++i) {
        if (std::abs(full[1].xdot[i] - v) < 1e-6 && full[1].x[i] >= fig6_min) {
          px.push_back(full[1].x[i]);
          pd.push_back(full[1].d[i]);
        }
      }
      f.series.push_back(MakeSeries(px, pd, "D(2) training points (DOB estimate)", "points"));
      report.AddFigure(f, o.out);
    }
  }
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
                            {"fig11_gp_estimate.png", "GP estimate (after the F-gp low-pass)", "GP estimate [N]", nullptr, "f_gp.d_hat_g", 1},
                            {"fig12_dob.png", "DOB output", "DOB output [N]", "dob.d_hat", "dob.d_hat", 1},
                            {"fig13_input.png", "Control input u", "u [N]", "u_c.y", "u.y", 1}};
    for (const Panel& p : panels) {
      Figure f = MakeFigure(p.file, p.title, "time [s]", p.ylabel);
      if (p.conv_signal) f.series.push_back(MakeSeries(t, Scaled(cases[0].result.log.Column(p.conv_signal), p.scale), "conv"));
      f.series.push_back(MakeSeries(cases[1].result.log.time, Scaled(cases[1].result.log.Column(p.gp_signal), p.scale), "DS"));
      f.series.push_back(MakeSeries(cases[2].result.log.time, Scaled(cases[2].result.log.Column(p.gp_signal), p.scale), "PS"));
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
      const std::pair<std::size_t, const char*> which[] = {
          {1, "DS"}, {2, "PS"}, {4, "DS + payload"}, {5, "PS + payload"}};
      for (const auto& [i, name] : which) {
        f.series.push_back(MakeSeries(cases[i].result.log.time, Scaled(cases[i].result.log.Column(signal), scale), name));
      }
      report.AddFigure(f, o.out);
    }
  }
  results["timing"]["reproduce_wall_time_s"] = elapsed();
  WriteJsonFile(results, o.out / "results.json");
  report.Write(o.out / "report.html");
  return results;
}

}  // namespace mb
