// reproduce, step 8 (second half): the paper's central claim — the periodic kernel keeps the cogging outside its
// training window, the SE kernel does not (Table 1) — on a real motor (issue 14). The records are a BLDC motor's
// holding current Iq against its angle (diagrams/odrive/data, README there): slow velocity-controlled
// revolutions at 0.1 rev/s (slow2/) and 0.03 rev/s (slow2_slower/), and the author's quasi-static cogging map
// (coggingmap_0/), measured by another method. DS and PS (period 1/7 rev, and the period the fit estimates) are
// trained on a window of the angle — a quarter, a half, three quarters of a revolution, as D(1)–D(3) — of the two
// training revolutions, and predict the rest of the revolution, the other revolutions and the map.
//
// Units: x is the angle [rev] and ẋ the record's mean speed [rev/s] (the constant velocity set point, as the paper's
// scans use the commanded velocity); d is Iq [A]. The map holds no friction (holding current), the records carry the
// Coulomb level of their direction: against the map each side's mean is removed.

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "models/diagnosis/measurement_log.h"
#include "models/gpr/gpr_fit.h"
#include "tools/experiments/paper/reproduce_context.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr double kCoggingPeriodRev = 1.0 / 7.0;  // 7 cycles per revolution (README of the data)
constexpr double kMotorWindow[3] = {0.25, 0.5, 0.75};  // training windows [rev], as D(1)–D(3)
constexpr int kMaxTrainingSamples = 1500;

struct MotorRecord {
  std::string name;
  Eigen::VectorXd angle;  ///< wrapped into [0, 1) rev
  Eigen::VectorXd iq;     ///< [A]
  double speed = 0.0;     ///< mean angular speed [rev/s]
};

// The fewest rows a record of this step may have: a revolution's records hold 4,000 to 15,000 rows, the map 512; a
// record of fewer is cut short (issue 41: a too-short record was taken without a word).
constexpr Eigen::Index kMinMotorRecordRows = 100;

// The records of the step, in the folder laid out as diagrams/odrive/data.
constexpr const char* kMapFile = "coggingmap_0_a_16.csv";

MotorRecord ReadRecord(const fs::path& file, const std::string& name) {
  MeasurementLogOptions read;
  read.required_columns = {"angle_rev", "iq_A"};
  read.max_gap_ratio = 0.0;  // USB-logged: jittered, with gaps; the order of the samples is all this step needs
  read.allow_repeated_times = true;
  read.min_rows = kMinMotorRecordRows;
  const MeasurementLog log = ReadMeasurementLog(file.string(), read);
  MotorRecord r{name, log.column("angle_rev"), log.column("iq_A"), 0.0};
  // The set-point speed, between the 10th and the 90th percent of the samples: nocomp_1 and _2 begin with a quick
  // return from the previous revolution's end, and per-sample speeds are biased by the jittered timestamps.
  const Eigen::VectorXd& t = log.time();
  const Eigen::Index lo = t.size() / 10, hi = t.size() - 1 - t.size() / 10;
  r.speed = (r.angle(hi) - r.angle(lo)) / (t(hi) - t(lo));
  if (!std::isfinite(r.speed) || r.speed == 0.0) {
    throw std::invalid_argument(fmt::format("{}: the angle does not advance over the record (mean speed {:g} rev/s): "
                                            "this step needs a revolution at a constant velocity",
                                            file.string(), r.speed));
  }
  r.angle = r.angle.unaryExpr([](double a) { return a - std::floor(a); });
  return r;
}

MotorRecord ReadMap(const fs::path& data) {
  MeasurementLogOptions map_read;
  map_read.required_columns = {"angle_rev", "iq_A"};
  map_read.min_rows = kMinMotorRecordRows;
  const MeasurementLog map_log = ReadMeasurementLog((data / kMapFile).string(), map_read);
  return {"coggingmap_0/a_16", map_log.column("angle_rev"), map_log.column("iq_A"), 0.0};
}

struct MotorRecords {
  MotorRecord fast, slow, other1, other2, map;
};

MotorRecords ReadMotorRecords(const fs::path& data) {
  return {ReadRecord(data / "slow2_nocomp_0.csv", "slow2/nocomp_0"),
          ReadRecord(data / "slow2_slower_nocomp_0.csv", "slow2_slower/nocomp_0"),
          ReadRecord(data / "slow2_nocomp_1.csv", "slow2/nocomp_1"),
          ReadRecord(data / "slow2_nocomp_2.csv", "slow2/nocomp_2"), ReadMap(data)};
}

struct Split {
  std::vector<double> x, xdot, d;
};

// The samples of `records` with angle inside [0, window) (inside = true) or outside it, every `stride`-th.
Split Select(const std::vector<const MotorRecord*>& records, double window, bool inside, int stride) {
  Split s;
  int k = 0;
  for (const MotorRecord* r : records) {
    for (Eigen::Index i = 0; i < r->angle.size(); ++i) {
      if ((r->angle(i) < window) != inside) continue;
      if (k++ % stride != 0) continue;
      s.x.push_back(r->angle(i));
      s.xdot.push_back(r->speed);
      s.d.push_back(r->iq(i));
    }
  }
  return s;
}

Eigen::Map<const Eigen::VectorXd> View(const std::vector<double>& v) {
  return {v.data(), static_cast<Eigen::Index>(v.size())};
}

double Rmse(const GprModel& m, const Split& s) {
  double sum = 0.0;
  for (std::size_t i = 0; i < s.x.size(); ++i) sum += std::pow(m.PredictPosteriorMean(s.x[i], s.xdot[i]) - s.d[i], 2);
  return s.x.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(s.x.size()));
}

// RMSE and correlation against the quasi-static map, each side's mean removed, at the slowest trained speed.
std::pair<double, double> AgainstMap(const GprModel& m, const MotorRecord& map, double speed) {
  Eigen::VectorXd p(map.angle.size());
  for (Eigen::Index i = 0; i < p.size(); ++i) p(i) = m.PredictPosteriorMean(map.angle(i), speed);
  const Eigen::VectorXd a = p.array() - p.mean();
  const Eigen::VectorXd b = map.iq.array() - map.iq.mean();
  return {std::sqrt((a - b).squaredNorm() / static_cast<double>(a.size())), a.dot(b) / (a.norm() * b.norm())};
}

// Amplitude of harmonic h (cycles per revolution) of the map, by least squares on its (uniform) angles.
double HarmonicAmplitude(const MotorRecord& map, int h) {
  double c = 0.0, s = 0.0;
  const double n = static_cast<double>(map.angle.size());
  for (Eigen::Index i = 0; i < map.angle.size(); ++i) {
    const double phase = 2.0 * std::numbers::pi * h * map.angle(i);
    c += map.iq(i) * std::cos(phase);
    s += map.iq(i) * std::sin(phase);
  }
  return 2.0 / n * std::hypot(c, s);
}

struct MotorFit {
  std::string kernel;  ///< "DS", "PS", "PS_estimated_period"
  int window;
  std::unique_ptr<GprModel> model;
};

}  // namespace

void CheckOdriveData(const ReproduceOptions& options) {
  if (options.odrive_data.empty()) return;  // the shipped folder: read, or skipped when absent
  const fs::path& data = options.odrive_data;
  std::error_code ec;
  if (!fs::is_directory(data, ec)) {
    throw std::invalid_argument(fmt::format("--odrive-data {}: {}; give the folder of the ODrive records (laid out as "
                                            "diagrams/odrive/data)",
                                            data.string(), fs::exists(data, ec) ? "not a folder" : "no such folder"));
  }
  try {
    (void)ReadMotorRecords(data);
  } catch (const std::exception& e) {
    throw std::invalid_argument(fmt::format("--odrive-data {}: {}", data.string(), e.what()));
  }
}

void RunRealMotor(ReproduceContext& c) {
  const bool named = !c.options.odrive_data.empty();
  const fs::path data =
      named ? c.options.odrive_data : (c.options.diagrams / ".." / "odrive" / "data").lexically_normal();
  c.Say(fmt::format("[8/{}] real motor: DS and PS on an ODrive BLDC motor's cogging ({})", kSteps, data.string()));
  if (!named && !fs::exists(data / kMapFile)) {  // skipped only when the shipped folder is not installed
    c.real_motor = {{"skipped", fmt::format("no ODrive records at {} (give --odrive-data DIR)", data.string())}};
    return;
  }
  const MotorRecords records = ReadMotorRecords(data);  // a folder named explicitly was checked before step 1
  const MotorRecord& fast = records.fast;
  const MotorRecord& slow = records.slow;
  const MotorRecord& other1 = records.other1;
  const MotorRecord& other2 = records.other2;
  const MotorRecord& map = records.map;

  const std::vector<const MotorRecord*> training = {&fast, &slow};
  std::vector<MotorFit> fits;
  for (int w = 0; w < 3; ++w) {
    for (const char* kernel : {"DS", "PS", "PS_estimated_period"}) fits.push_back({kernel, w, nullptr});
  }
  const double slowest = slow.speed;  // the 0.03 rev/s revolution: nearest the map's quasi-static holding
  c.arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, fits.size(), [&](std::size_t i) {
      MotorFit& f = fits[i];
      const Split all = Select(training, kMotorWindow[f.window], true, 1);
      const int stride = std::max(1, static_cast<int>(all.x.size()) / kMaxTrainingSamples);
      const Split s = Select(training, kMotorWindow[f.window], true, stride);
      GprFitOptions o;
      o.kernel = f.kernel == std::string("DS") ? GprKernel::kSeSe : GprKernel::kPeriodicSe;
      o.period = kCoggingPeriodRev;
      o.estimate_period = f.kernel == std::string("PS_estimated_period");
      o.restarts = c.options.quick ? 0 : 2;
      o.source = "odrive_cogging slow2/nocomp_0 + slow2_slower/nocomp_0";
      f.model = std::make_unique<GprModel>(FitGpr(View(s.x), View(s.xdot), View(s.d), o));
    });
  });

  json rows = json::array();
  for (const MotorFit& f : fits) {
    const double window = kMotorWindow[f.window];
    const auto [map_rmse, map_r] = AgainstMap(*f.model, map, slowest);
    rows.push_back({{"kernel", f.kernel},
                    {"window", kWindowName[f.window]},
                    {"window_rev", window},
                    {"period_rev", f.model->hyperparameters().period},
                    {"training_samples", f.model->data().provenance.sample_count},
                    {"rmse_inside_window_A", Rmse(*f.model, Select(training, window, true, 1))},
                    {"rmse_rest_of_revolution_A", Rmse(*f.model, Select(training, window, false, 1))},
                    {"rmse_other_revolutions_A", Rmse(*f.model, Select({&other1, &other2}, 2.0, true, 1))},
                    {"rmse_against_map_A", map_rmse},
                    {"correlation_with_map", map_r}});
  }
  json harmonics;
  double multiples_of_7 = 0.0, others = 0.0;
  for (int h = 1; h <= 64; ++h) {
    const double a = HarmonicAmplitude(map, h);
    (h % 7 == 0 ? multiples_of_7 : others) += 0.5 * a * a;  // power of a sinusoid of amplitude a
    if (h == 7 || h == 12 || h == 14 || h == 28 || h == 36) harmonics[fmt::format("{}", h)] = a;
  }
  c.real_motor = {{"unit", "A"},
                  {"records", {fast.name, slow.name, other1.name, other2.name, map.name}},
                  {"speeds_rev_per_s", {fast.speed, slow.speed, other1.speed, other2.speed}},
                  {"rows", rows},
                  {"map_harmonic_amplitudes_A", harmonics},
                  {"map_power_share_not_multiple_of_7", others / (others + multiples_of_7)}};
  // For the figure: the D(2) models over one revolution.
  c.real_motor_curves.clear();
  for (const MotorFit& f : fits) {
    if (f.window != 1) continue;
    std::vector<double> mu;
    for (Eigen::Index i = 0; i < map.angle.size(); ++i) mu.push_back(f.model->PredictPosteriorMean(map.angle(i), slowest));
    c.real_motor_curves[f.kernel] = mu;
  }
  c.real_motor_curves["map_angle"] = std::vector<double>(map.angle.data(), map.angle.data() + map.angle.size());
  c.real_motor_curves["map"] = std::vector<double>(map.iq.data(), map.iq.data() + map.iq.size());
}

}  // namespace mb::paper
