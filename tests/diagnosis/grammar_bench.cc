#include "tests/diagnosis/grammar_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "models/diagnosis/effect_registry.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement.h"

namespace mb::grammar {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kCleanShare = 0.02;  // a noise-only draw: nothing named with this share or more

const fs::path kSource = fs::path(MB_SOURCE_DIR);

fs::path DiagramFolder(const GrammarDraw& d) { return kSource / "diagrams" / (d.rotary ? "rotary" : "emps"); }
std::string DiagramFile(const GrammarDraw& d) { return d.rotary ? "rigid_arm.json" : "rigid_body.json"; }

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

bool IsLaw(const std::string& effect) { return LookupEffect(effect).traits.friction_law_replacement; }

std::string PairName(const std::string& effect) {
  const auto [multiplier, modulator] = FactorsOf(effect);
  return multiplier.empty() ? effect : multiplier + "×" + modulator;
}

MeasurementLog WriteAndRead(const Record& record, const fs::path& path, const json& diagram,
                            const MeasurementSettings& settings) {
  WriteCsv(record, path.string());
  return ReadMeasurementFor(diagram, path.string(), settings);
}

bool Within(double found, double truth, double tolerance) { return std::abs(found - truth) <= tolerance; }

// A pair as the force law it is: a multiplier × 1 whose amplitude follows time (the generator's third factor
// 1 + β·(2t/T − 1), the diagnosis' (t − t₀)/h: both linear in t) is that multiplier × time_ramp with its level, and one
// whose amplitude follows a column is that multiplier × the column with its level — the same columns under two names.
struct ForceLaw {
  std::string multiplier, modulator, column;
  bool operator==(const ForceLaw&) const = default;
};
ForceLaw LawOf(std::string multiplier, std::string modulator, std::string column, const std::string& third) {
  if (modulator == "constant" && third == "time") return {std::move(multiplier), "time_ramp", ""};
  if (modulator == "constant" && !third.empty()) return {std::move(multiplier), "column", third};
  return {std::move(multiplier), std::move(modulator), std::move(column)};
}

// Names, parameters and the verdicts of compare's diagnosis.
void Judge(const DiagnosisResult& diagnosis, DrawResult* r) {
  const GrammarDraw& d = r->draw;
  r->parameter = r->second_parameter = std::numeric_limits<double>::quiet_NaN();
  const DiagnosedEffect* first = nullptr;
  double largest = 0.0;
  for (const auto& e : diagnosis.effects) {
    const bool law = IsLaw(e.effect);
    std::string placed;  // where the record places each change time (DiagnosedEffect::time_intervals)
    for (const auto& [name, interval] : e.time_intervals) {
      placed += fmt::format(", {} placed in [{:.4g}, {:.4g}] s", name, interval[0], interval[1]);
    }
    r->details.push_back(fmt::format("{}{}: score {:.4f}, {}{}{}", e.effect, law ? " (law)" : "", e.score,
                                     fmt::join(e.parameters, ", "),
                                     e.log_column.empty() ? "" : ", column " + e.log_column, placed));
    if (law) continue;
    if (first == nullptr) first = &e;
    largest = std::max(largest, e.score);
  }
  r->details.insert(r->details.end(), diagnosis.notes.begin(), diagnosis.notes.end());
  r->clean = largest < kCleanShare;
  if (first == nullptr) {
    r->named_pair = "nothing";
    return;
  }
  r->named_first = first->effect;
  r->named_score = first->score;
  r->named_pair = PairName(first->effect);
  r->log_column = first->log_column;
  if (const auto with = first->parameters.find("amplitude_with"); with != first->parameters.end()) {
    r->third_found = with->second < 0.0 ? std::string("time") : first->amplitude_column;
    r->third_slope = first->parameters.at("amplitude_slope");
  }
  if (d.noise_only) return;
  const auto [multiplier, modulator] = FactorsOf(first->effect);
  const ForceLaw named = LawOf(multiplier, modulator, first->log_column, r->third_found);
  const ForceLaw drawn =
      LawOf(d.multiplier, d.modulator, d.active_column.name,
            d.third_factor == "column" ? d.third_column.name : d.third_factor);
  r->named_right = d.effect.empty() ? named.multiplier == drawn.multiplier && named.modulator == drawn.modulator
                                    : first->effect == d.effect;
  r->third_in_law = r->named_right && d.modulator == "constant" && !d.third_factor.empty();
  for (const std::string& alike : first->alike) {
    const auto [m, mod] = FactorsOf(alike);
    r->alike_right = r->alike_right || (!r->named_right && m == d.multiplier && mod == d.modulator);
  }
  bool shape = true;
  if (!d.key_parameter.empty()) {
    const auto it = first->parameters.find(d.key_parameter);
    if (it != first->parameters.end()) r->parameter = it->second;
    shape = Within(r->parameter, d.key_value, d.key_tolerance);
  }
  if (!d.second_parameter.empty()) {
    const auto it = first->parameters.find(d.second_parameter);
    if (it != first->parameters.end()) r->second_parameter = it->second;
    shape = shape && Within(r->second_parameter, d.second_value, d.key_tolerance);
  }
  if (!drawn.column.empty()) shape = shape && named.column == drawn.column;
  r->parameter_right = r->named_right && shape;
  if (const auto it = first->time_intervals.find(d.key_parameter); r->named_right && it != first->time_intervals.end()) {
    r->interval_judged = true;
    r->interval_holds = it->second[0] <= d.key_value && d.key_value <= it->second[1];
    r->interval_width = (it->second[1] - it->second[0]) / d.duration;
  }
}

}  // namespace

std::pair<std::string, std::string> FactorsOf(const std::string& effect) {
  const EffectType& type = LookupEffect(effect);
  return {type.multiplier, type.modulator};
}

DrawResult RunDraw(const GrammarDraw& draw, const fs::path& directory, bool run_improve) {
  DrawResult r;
  r.draw = draw;
  fs::create_directories(directory);
  const json diagram = ReadDiagramJson(DiagramFolder(draw) / DiagramFile(draw));
  ImproveSettings settings;
  if (draw.rotary) settings.measurement.position_column = "angle_rad";
  // The controller's command is logged as it was sent and held by the drive until the next sample.
  settings.measurement.intersample = Intersample::kZeroOrderHold;
  settings.measurement.every_pair = true;  // the whole grammar: what the draws test
  const MeasurementLog training =
      WriteAndRead(Simulate(draw, Run::kTraining), directory / "training.csv", diagram, settings.measurement);
  const auto t0 = std::chrono::steady_clock::now();
  const DiagnosedComparison compared = CompareAndDiagnose(diagram, DiagramFolder(draw), DiagramFile(draw), training,
                                                          settings.measurement, diagram["free"]);
  r.compare_seconds = Seconds(t0);
  if (!compared.diagnosis) throw std::runtime_error("no diagnosis: " + compared.diagnosis_skipped);
  Judge(*compared.diagnosis, &r);
  if (!run_improve || draw.noise_only) return r;
  r.improve_run = true;
  const MeasurementLog validation =
      WriteAndRead(Simulate(draw, Run::kValidation), directory / "validation.csv", diagram, settings.measurement);
  // The draw's own floor (issue 45): the same draw simulated without the effect, improved as the draw is (the base
  // refit, and the friction law near zero velocity that the base's sign(v) does not hold replaced) and scored on its
  // validation twin — what the pipeline reaches where nothing is hidden, its derivatives' edge transients included.
  const MeasurementLog twin = WriteAndRead(Simulate(draw, Run::kValidation, false), directory / "validation_twin.csv",
                                           diagram, settings.measurement);
  const MeasurementLog training_twin = WriteAndRead(Simulate(draw, Run::kTraining, false),
                                                    directory / "training_twin.csv", diagram, settings.measurement);
  r.noise_floor = ImproveModel(DiagramDocument(diagram, DiagramFolder(draw), DiagramFile(draw)), training_twin, &twin,
                               settings)
                      .last_accepted()
                      .rmse_heldout;
  const auto t1 = std::chrono::steady_clock::now();
  const ImproveResult improved = ImproveModel(DiagramDocument(diagram, DiagramFolder(draw), DiagramFile(draw)),
                                              training, &validation, settings);
  r.improve_seconds = Seconds(t1);
  r.heldout_before = improved.first().rmse_heldout;
  r.heldout_after = improved.last_accepted().rmse_heldout;
  r.floor_reached = r.heldout_after >= 0.7 * r.noise_floor && r.heldout_after <= 1.3 * r.noise_floor;
  for (const ImproveStep& step : improved.steps) {
    if (step.round > 0) r.details.push_back(fmt::format("improve round {}: {}: {}", step.round, step.effect, step.verdict));
  }
  r.details.push_back("improve stopped: " + improved.stop_reason);
  return r;
}

namespace {

std::string Rate(int passed, int of) {
  return of == 0 ? "—" : fmt::format("{} of {} ({:.0f} %)", passed, of, 100.0 * passed / of);
}

struct Tally {
  int draws = 0, named = 0, parameter = 0, improved = 0, floor = 0;
  std::map<std::string, int> named_first;  // what was named first, with counts
  void Add(const DrawResult& r) {
    ++draws;
    named += r.named_right ? 1 : 0;
    parameter += r.parameter_right ? 1 : 0;
    improved += r.improve_run ? 1 : 0;
    floor += r.floor_reached ? 1 : 0;
    ++named_first[r.named_pair];
  }
};

std::string Counts(const std::map<std::string, int>& counts) {
  std::vector<std::pair<int, std::string>> sorted;
  for (const auto& [name, count] : counts) sorted.emplace_back(-count, name);
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::string> parts;
  for (const auto& [count, name] : sorted) parts.push_back(fmt::format("{} {}", name, -count));
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string TallyTable(const std::string& heading, const std::map<std::string, Tally>& rows, bool with_names) {
  std::string out = fmt::format("| {} | draws | named | parameter | floor |{}\n|---|---|---|---|---|{}\n", heading,
                                with_names ? " named first (count) |" : "", with_names ? "---|" : "");
  for (const auto& [name, t] : rows) {
    out += fmt::format("| {} | {} | {} | {} | {} |{}\n", name, t.draws, t.named, t.parameter,
                       t.improved == 0 ? "—" : fmt::format("{} of {}", t.floor, t.improved),
                       with_names ? " " + Counts(t.named_first) + " |" : "");
  }
  return out;
}

}  // namespace

std::string FormatReport(const std::vector<DrawResult>& draws, const std::vector<DrawResult>& noise_only,
                         const std::string& title) {
  Tally all;
  std::map<std::string, Tally> by_pair, by_multiplier, by_modulator;
  double compare_total = 0.0, compare_max = 0.0, improve_total = 0.0;
  for (const auto& r : draws) {
    all.Add(r);
    by_pair[r.draw.pair()].Add(r);
    by_multiplier[r.draw.multiplier].Add(r);
    by_modulator[r.draw.modulator].Add(r);
    compare_total += r.compare_seconds;
    compare_max = std::max(compare_max, r.compare_seconds);
    improve_total += r.improve_seconds;
  }
  std::string out = "## " + title + "\n\n";
  if (!draws.empty()) {
    out += fmt::format("Seeds {}–{}; compare {:.2f} s per draw on average (longest {:.2f} s){}.\n\n",
                       draws.front().draw.seed, draws.back().draw.seed, compare_total / static_cast<double>(draws.size()),
                       compare_max,
                       all.improved == 0 ? ", improve not run"
                                         : fmt::format(", improve {:.1f} s", improve_total / all.improved));
  }
  out += "| criterion | pass |\n|---|---|\n";
  out += fmt::format("| named right (the first effect outside the law replacements has the drawn multiplier × "
                     "modulator) | {} |\n",
                     Rate(all.named, all.draws));
  out += fmt::format("| parameter right (named right and its key shape parameter, or column, within tolerance) | {} |\n",
                     Rate(all.parameter, all.draws));
  int alike = 0;
  for (const auto& r : draws) alike += r.alike_right ? 1 : 0;
  out += fmt::format("| not named right, but the drawn pair is the one the diagnosis said it cannot tell from the one "
                     "it named (not counted above) | {} |\n",
                     Rate(alike, all.draws));
  out += fmt::format("| floor reached (improve's held-out RMSE within [0.7, 1.3] × the floor) | {} |\n\n",
                     all.improved == 0 ? std::string("not run") : Rate(all.floor, all.improved));
  // The third factor (the amplitude following time or a further column): found with its source on the draws named
  // right that carry one; found on the draws named right that carry none.
  int carry = 0, found = 0, spare = 0, invented = 0;
  for (const auto& r : draws) {
    if (!r.named_right) continue;
    const std::string truth = r.draw.third_factor == "column" ? r.draw.third_column.name : r.draw.third_factor;
    if (!truth.empty()) {
      ++carry;
      found += r.third_found == truth || r.third_in_law ? 1 : 0;
    } else {
      ++spare;
      invented += r.third_found.empty() ? 0 : 1;
    }
  }
  out += fmt::format("Third factor, on the draws named right: found with its source on {} that carry one; a third "
                     "factor named on {} that carry none.\n\n",
                     Rate(found, carry), Rate(invented, spare));
  // The change times' intervals (DiagnosedEffect::time_intervals): how often they hold the drawn time, how wide.
  int judged = 0, holds = 0, estimate_within = 0;
  double width = 0.0;
  for (const auto& r : draws) {
    if (!r.interval_judged) continue;
    ++judged;
    holds += r.interval_holds ? 1 : 0;
    estimate_within += r.parameter_right ? 1 : 0;
    width += r.interval_width;
  }
  out += fmt::format("Change times, on the draws named right with one as their key parameter: the interval holds the "
                     "drawn time on {} (the estimate within the tolerance on {}); its mean width {:.1f} % of the "
                     "record.\n\n",
                     Rate(holds, judged), Rate(estimate_within, judged), judged > 0 ? 100.0 * width / judged : 0.0);
  int clean = 0;
  std::map<std::string, int> noise_named;
  for (const auto& r : noise_only) {
    clean += r.clean ? 1 : 0;
    if (!r.clean) ++noise_named[r.named_pair];
  }
  out += fmt::format("Noise-only draws: {} clean (nothing outside the friction-law replacements named with a share ≥ "
                     "{}){}.\n\n",
                     Rate(clean, static_cast<int>(noise_only.size())), kCleanShare,
                     noise_named.empty() ? "" : "; named: " + Counts(noise_named));
  out += "### By multiplier\n\n" + TallyTable("multiplier", by_multiplier, false) + "\n";
  out += "### By modulator\n\n" + TallyTable("modulator", by_modulator, false) + "\n";
  out += "### Confusion (rows: the drawn multiplier × modulator; what was named first, with counts)\n\n" +
         TallyTable("drawn", by_pair, true);
  return out;
}

std::string ConfusionCsv(const std::vector<DrawResult>& draws) {
  std::set<std::string> columns;
  std::map<std::string, std::map<std::string, int>> rows;
  for (const auto& r : draws) {
    columns.insert(r.named_pair);
    ++rows[r.draw.pair()][r.named_pair];
  }
  std::string out = "drawn";
  for (const auto& c : columns) out += "," + c;
  out += "\n";
  for (const auto& [pair, counts] : rows) {
    out += pair;
    for (const auto& c : columns) {
      const auto it = counts.find(c);
      out += fmt::format(",{}", it == counts.end() ? 0 : it->second);
    }
    out += "\n";
  }
  return out;
}

std::string ResultsCsv(const std::vector<DrawResult>& draws) {
  std::string out =
      "seed,drawn,named_first,named_pair,score,key_parameter,found,truth,tolerance,named_right,parameter_right,"
      "ratio,generator_floor,floor,heldout_before,heldout_after,floor_reached,compare_s,improve_s,rotary,sample_rate_hz,"
      "trajectory,third_factor,interval_holds,interval_width\n";
  for (const auto& r : draws) {
    const GrammarDraw& d = r.draw;
    out += fmt::format("{},{},{},{},{:.4f},{},{:.6g},{:.6g},{:.3g},{},{},{:.2f},{:.4g},{:.4g},{:.4g},{:.4g},{},{:.3f},"
                       "{:.2f},{},{:.0f},{},{},{},{:.4f}\n",
                       d.seed, d.pair(), r.named_first, r.named_pair, r.named_score, d.key_parameter, r.parameter,
                       d.key_value, d.key_tolerance, r.named_right, r.parameter_right, d.target_ratio, d.noise_floor,
                       r.noise_floor, r.heldout_before, r.heldout_after, r.floor_reached, r.compare_seconds,
                       r.improve_seconds, d.rotary, d.sample_rate,
                       d.trajectory == Trajectory::kSweep ? "sweep" : "point_to_point", d.third_factor,
                       r.interval_judged ? (r.interval_holds ? "true" : "false") : "", r.interval_width);
  }
  return out;
}

}  // namespace mb::grammar
