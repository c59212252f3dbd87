// reproduce, step 7 (beyond the paper, issue 14): learning online. The gpr block's learning "online" (blocks/gpr.h,
// models/gpr/gpr_recursive.h) in the Fig. 8 loop, diagrams/paper/gp_loop_online.json: the posterior over the basis
// weights is updated at every 1 ms step from gp_target = d̂ + Q·d̂_g (= Q·d, what the offline model was trained on),
// with exponential forgetting bounded by the prior.
//  (a) Table 2's cases with learning online (same Fig. 9 runs): from the PS model of D(2), without and with the
//      payload it was not trained with, and from no data (the prior).
//  (b) A payload picked up mid-run: a long forward run alternating 150 and 350 mm/s (the Fig. 9 speeds; an endless
//      track, as a rotary table or a conveyor mover sees it), the payload put on at half time; the tracking RMSE of
//      each constant-speed segment for the conventional loop, the fixed PS model, the learner started from it and
//      the learner started from no data. (Measured: learning online does not absorb the payload, whose force m_p·ẍ
//      is not a function of (x, ẋ); docs/paper.md.)
//  (c) The mass learned online (blocks/adaptive_mass_feedforward.h, diagrams/paper/gp_loop_adaptive_mass.json: the
//      command scaled by (M_n + Δm̂)/M_n) with the PS models trained on the DOB estimate and on the smoothed estimate,
//      in (a)'s Fig. 9 runs (and with α = 0: the conventional loop plus the mass) and in (b)'s track.

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "tools/experiments/paper/reproduce_context.h"

namespace mb::paper {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kSegment = 1.2;      // [s] between speed changes (Fig. 9's transition starts)
constexpr double kForgetting = 0.9999;  // λ: a memory of about 10 s at 1 kHz

// The endless-track reference: 150 and 350 mm/s alternating every 1.2 s, `segments` segments, and the payload
// picked up at half time.
Assignments TrackRun(int segments) {
  json velocities = json::array();
  json starts = json::array();
  for (int k = 0; k < segments; ++k) {
    velocities.push_back(k % 2 == 0 ? 0.15 : 0.35);
    starts.push_back(kSegment * k);
  }
  const double stop = kSegment * segments;
  return {{"reference.velocities", velocities},    {"reference.transition_starts", starts},
          {"reference_ff.velocities", velocities}, {"reference_ff.transition_starts", starts},
          {"plant.payload_mass", kPayloadMass},    {"plant.payload_time", 0.5 * stop},
          {"defaultExperiment.stopTime", stop}};
}

Assignments With(Assignments a, const Assignments& more) {
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

// The learner: the PS model of D(2) (or its prior), forgetting λ.
Assignments Learner(const std::string& model, const char* learn_from = "model") {
  return {{"gpr.model", model}, {"gpr.forgetting", kForgetting}, {"gpr.learn_from", learn_from}};
}

// Tracking RMSE [µm] of each 1.2 s segment, from the second 0.2 s of it (after the speed change's transition).
std::vector<double> SegmentRmseUm(const SignalLog& log, int segments) {
  const auto& e = log.Column("error.y");
  std::vector<double> sum(static_cast<std::size_t>(segments), 0.0), n(static_cast<std::size_t>(segments), 0.0);
  for (std::size_t i = 0; i < e.size(); ++i) {
    const int k = static_cast<int>(log.time[i] / kSegment);
    if (k < 0 || k >= segments) continue;
    sum[static_cast<std::size_t>(k)] += e[i] * e[i];
    n[static_cast<std::size_t>(k)] += 1.0;
  }
  std::vector<double> rmse;
  for (int k = 0; k < segments; ++k) {
    const auto s = static_cast<std::size_t>(k);
    rmse.push_back(n[s] > 0.0 ? std::sqrt(sum[s] / n[s]) * 1e6 : 0.0);
  }
  return rmse;
}

// The adaptive feedforward's mass estimate at the end of a run [kg].
double FinalMass(const SignalLog& log) { return log.Column("mass_ff.mass").back(); }

// Step 7's runs, each at its OnlineCase (`segments`: the track's).
std::vector<ClosedLoopCase> OnlineCases(const ReproduceContext& c, int segments) {
  const std::string ps = c.model_paths.at("PS_D2").string();
  const std::string ps_smoothed = c.ps_smoothed_target_path.string();
  const Assignments track = TrackRun(segments);
  const Assignments payload = {{"plant.payload_mass", kPayloadMass}};
  const fs::path& mass = c.gp_loop_adaptive_mass;
  std::vector<ClosedLoopCase> cases(kOnlineCaseCount);
  const auto run = [&](OnlineCase which, std::string name, const fs::path& diagram, Assignments assignments) {
    cases[static_cast<std::size_t>(which)] = {std::move(name), diagram, std::move(assignments), {}};
  };
  run(OnlineCase::kPsOnline, "PS_online", c.gp_loop_online, Learner(ps));
  run(OnlineCase::kPsOnlinePayload, "PS_online_payload", c.gp_loop_online, With(Learner(ps), payload));
  run(OnlineCase::kPsOnlineFromPrior, "PS_online_from_prior", c.gp_loop_online, Learner(ps, "prior"));
  run(OnlineCase::kPsMass, "PS_mass", mass, {{"gpr.model", ps}});
  run(OnlineCase::kPsMassPayload, "PS_mass_payload", mass, With({{"gpr.model", ps}}, payload));
  run(OnlineCase::kPsSmoothedMass, "PS_smoothed_mass", mass, {{"gpr.model", ps_smoothed}});
  run(OnlineCase::kPsSmoothedMassPayload, "PS_smoothed_mass_payload", mass,
      With({{"gpr.model", ps_smoothed}}, payload));
  run(OnlineCase::kMassOnly, "mass_only", mass, {{"gpr.model", ps}, {"f_gp.weight", 0.0}});
  run(OnlineCase::kMassOnlyPayload, "mass_only_payload", mass,
      With({{"gpr.model", ps}, {"f_gp.weight", 0.0}}, payload));
  run(OnlineCase::kTrackConventional, "track_conventional", c.conventional, track);
  run(OnlineCase::kTrackPs, "track_PS", c.gp_loop, With(track, {{"gpr.model", ps}}));
  run(OnlineCase::kTrackPsOnline, "track_PS_online", c.gp_loop_online, With(track, Learner(ps)));
  run(OnlineCase::kTrackOnlineFromPrior, "track_online_from_prior", c.gp_loop_online,
      With(track, Learner(ps, "prior")));
  run(OnlineCase::kTrackPsMass, "track_PS_mass", mass, With(track, {{"gpr.model", ps}}));
  run(OnlineCase::kTrackPsSmoothed, "track_PS_smoothed", c.gp_loop, With(track, {{"gpr.model", ps_smoothed}}));
  run(OnlineCase::kTrackPsSmoothedMass, "track_PS_smoothed_mass", mass, With(track, {{"gpr.model", ps_smoothed}}));
  return cases;
}

}  // namespace

void LearnOnline(ReproduceContext& c) {
  const int segments = c.options.quick ? 6 : 10;
  c.Say(fmt::format("[7/{}] learning online: Table 2's payload case, and a payload picked up at {:.1f} s of a {:.1f} s "
                    "run",
                    kSteps, 0.5 * kSegment * segments, kSegment * segments));
  c.online_cases = OnlineCases(c, segments);
  c.arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, c.online_cases.size(), [&](std::size_t i) {
      c.online_cases[i].result = Simulate(c.online_cases[i].diagram, c.online_cases[i].assignments);
    });
  });
  const auto rmse = [&](OnlineCase which) { return c.OnlineRmseUm(which); };
  json track_json = {{"segment_s", kSegment},
                     {"payload_time_s", 0.5 * kSegment * segments},
                     {"segment_start_s", json::array()},
                     {"segment_speed_m_s", json::array()}};
  for (int k = 0; k < segments; ++k) {
    track_json["segment_start_s"].push_back(kSegment * k);
    track_json["segment_speed_m_s"].push_back(k % 2 == 0 ? 0.15 : 0.35);
  }
  for (std::size_t i = static_cast<std::size_t>(OnlineCase::kTrackConventional); i < kOnlineCaseCount; ++i) {
    const auto which = static_cast<OnlineCase>(i);
    const ClosedLoopCase& k = c.Online(which);
    track_json["segment_rmse_um"][k.name.substr(6)] = SegmentRmseUm(k.result.log, segments);  // less "track_"
    track_json["rmse_um"][k.name.substr(6)] = rmse(which);
  }
  const double ps_no_payload = c.RmseUm(PaperCase::kPs);
  c.online = {{"unit", "µm"},
              {"forgetting", kForgetting},
              {"table2",
               {{"PS", ps_no_payload},
                {"PS_payload", c.RmseUm(PaperCase::kPsPayload)},
                {"PS_online", rmse(OnlineCase::kPsOnline)},
                {"PS_online_payload", rmse(OnlineCase::kPsOnlinePayload)},
                {"PS_online_from_prior", rmse(OnlineCase::kPsOnlineFromPrior)},
                {"conventional", c.RmseUm(PaperCase::kConventional)},
                {"PS_online_over_conventional", rmse(OnlineCase::kPsOnline) / c.RmseUm(PaperCase::kConventional)},
                {"payload_over_no_payload_fixed", c.RmseUm(PaperCase::kPsPayload) / ps_no_payload},
                {"payload_over_no_payload_online", rmse(OnlineCase::kPsOnlinePayload) / ps_no_payload}}},
              {"adaptive_mass_feedforward",
               {{"PS_mass", rmse(OnlineCase::kPsMass)},
                {"PS_mass_payload", rmse(OnlineCase::kPsMassPayload)},
                {"PS_smoothed_mass", rmse(OnlineCase::kPsSmoothedMass)},
                {"PS_smoothed_mass_payload", rmse(OnlineCase::kPsSmoothedMassPayload)},
                {"mass_only", rmse(OnlineCase::kMassOnly)},
                {"mass_only_payload", rmse(OnlineCase::kMassOnlyPayload)},
                {"PS_smoothed", c.RmseUm(PaperCase::kPsSmoothed)},
                {"PS_smoothed_payload", c.RmseUm(PaperCase::kPsSmoothedPayload)},
                {"mass_estimate_payload_kg", FinalMass(c.Online(OnlineCase::kPsMassPayload).result.log)},
                {"mass_estimate_no_payload_kg", FinalMass(c.Online(OnlineCase::kPsMass).result.log)},
                {"mass_estimate_smoothed_payload_kg",
                 FinalMass(c.Online(OnlineCase::kPsSmoothedMassPayload).result.log)},
                {"payload_over_no_payload_PS_mass", rmse(OnlineCase::kPsMassPayload) / ps_no_payload},
                {"payload_over_no_payload_PS_smoothed_mass",
                 rmse(OnlineCase::kPsSmoothedMassPayload) / c.RmseUm(PaperCase::kPsSmoothed)},
                {"PS_smoothed_mass_payload_over_conventional",
                 rmse(OnlineCase::kPsSmoothedMassPayload) / c.RmseUm(PaperCase::kConventional)}}},
              {"track", track_json}};
  c.results["online_learning"] = c.online;
}

}  // namespace mb::paper
