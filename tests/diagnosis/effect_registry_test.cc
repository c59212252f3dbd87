// The effect registry (models/diagnosis/effect_registry.h): every registered effect is complete, names are
// unique, lookups of unknown names say "did you mean".
#include "models/diagnosis/effect_registry.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/parameter_text.h"
#include "models/diagnosis/signal_processing.h"
#include "tests/error_message.h"

namespace mb {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// Back and forth over 0..0.2 m at 1 kHz, with a model output.
DiagnosisSignals Motion() {
  const Eigen::Index n = 4000;
  DiagnosisSignals s;
  s.time = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  const Eigen::ArrayXd phase = 2.0 * std::numbers::pi * 0.5 * s.time.array();
  s.position = 0.1 + 0.1 * phase.sin();
  s.velocity = 0.1 * std::numbers::pi * phase.cos();
  s.acceleration = -0.1 * std::numbers::pi * std::numbers::pi * phase.sin();
  s.residual = Eigen::VectorXd::Zero(n);
  s.model_output = 90.0 * s.acceleration + 200.0 * s.velocity;
  s.logged_command = s.model_output;  // equation-error mode: the command the drive was given
  s.extra_names = {"accel_y_m_s2"};  // a column the diagram does not read (logged_column)
  s.extra_columns = {0.5 * s.acceleration.reverse()};
  return s;
}

// A typical value of every parameter an effect declares. A new effect's new parameter goes here too, so that the
// test builds its regressors.
const std::map<std::string, double> kTypical{{"period", 0.0025},   {"harmonics", 2.0},         {"frequency_hz", 7.0},
                                             {"delay", 0.004},     {"stribeck_velocity", 0.01}, {"damping_ratio", 0.05},
                                             {"step", 0.5},        {"dead_band", 0.001},        {"slip_velocity", 0.002},
                                             {"backlash", 1e-3},   {"center", 0.1},            {"half_range", 0.1},
                                             {"degree", 3.0},      {"regularization_velocity", 5e-4},
                                             {"presliding_displacement", 2e-5}, {"lag", 0.004},
                                             {"upper_limit", 50.0}, {"lower_limit", -60.0}, {"change_time", 2.0}, {"own_level", 1.0},
                                             {"start_time", 0.0}, {"end_time", 4.0}, {"half_width", 0.02},
                                             {"column", 0.0},      {"time_constant", 1.5},     {"speed_slope", 100.0},
                                             {"no_load_speed", 0.5}, {"on_time", 1.0},     {"off_time", 3.0},
                                             {"min_breakaway", 1e-3}, {"max_breakaway", 0.02}, {"elements", 5.0},
                                             {"stroke", 0.01},     {"breakaway_force", 10.0},  {"initial_stiffness", 1e4},
                                             {"drift_rate", 0.5},  {"load_damping", 1.0},      {"load_mass", 10.0}};

bool IsSnakeCase(const std::string& name) {
  return !name.empty() && std::islower(static_cast<unsigned char>(name.front())) &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_';
         });
}

TEST(EffectRegistry, EveryEffectHasNamePhysicsRegressorsAndARule) {
  const auto effects = EffectRegistry::Global().Effects();
  ASSERT_GE(effects.size(), 12u);
  for (const EffectType* e : effects) {
    SCOPED_TRACE(e->name);
    EXPECT_TRUE(IsSnakeCase(e->name));
    EXPECT_FALSE(e->physics.empty());
    EXPECT_FALSE(e->regressor_formula.empty());
    EXPECT_TRUE(e->regressors);
    EXPECT_TRUE(e->propose);
    for (const auto& p : e->parameters) {
      EXPECT_TRUE(IsSnakeCase(p.name));
      EXPECT_FALSE(p.description.empty()) << p.name;
    }
    if (e->block) {
      EXPECT_FALSE(e->block->block_type.empty());
      EXPECT_FALSE(e->block->element_name.empty());
      EXPECT_TRUE(e->block->parameters);
    }
    if (e->traits.periodicity == Periodicity::kPosition) {
      EXPECT_TRUE(std::any_of(e->parameters.begin(), e->parameters.end(), [](const auto& p) { return p.name == "period"; }));
    }
  }
}

TEST(EffectRegistry, NamesAreUniqueAndInCatalogueOrder) {
  const std::vector<std::string> names = EffectNames();
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  const auto effects = EffectRegistry::Global().Effects();
  ASSERT_EQ(effects.size(), names.size());
  for (std::size_t i = 0; i < effects.size(); ++i) {
    EXPECT_EQ(effects[i]->name, names[i]);
    if (i > 0) {
      EXPECT_LE(effects[i - 1]->catalogue_order, effects[i]->catalogue_order);
    }
  }
  // The catalogue's stable names (compare.json) are all there.
  for (const char* name : {"constant_offset", "viscous_friction", "coulomb_friction", "asymmetric_friction",
                           "stribeck_friction", "mass_mismatch", "position_periodic", "velocity_dependent_ripple",
                           "time_periodic", "resonance", "time_delay", "quantization", "backlash",
                           "position_dependent_force", "regularized_coulomb_friction", "presliding_friction"}) {
    EXPECT_NE(EffectRegistry::Global().Find(name), nullptr) << name;
  }
}

TEST(EffectRegistry, RegressorsBuildFromTheDeclaredParameters) {
  const DiagnosisSignals s = Motion();
  for (const EffectType* e : EffectRegistry::Global().Effects()) {
    SCOPED_TRACE(e->name);
    EffectInstance instance{e->name, {}};
    for (const auto& p : e->parameters) {
      ASSERT_TRUE(kTypical.count(p.name)) << "add a typical value of '" << p.name << "' to kTypical";
      instance.parameters[p.name] = kTypical.at(p.name);
    }
    const EffectRegressors reg = BuildEffectRegressors(instance, s);
    EXPECT_EQ(reg.columns.rows(), s.size());
    ASSERT_GE(reg.columns.cols(), 1);
    ASSERT_EQ(static_cast<Eigen::Index>(reg.column_names.size()), reg.columns.cols());
    EXPECT_TRUE(reg.columns.allFinite());
    for (const auto& column : reg.column_names) {
      EXPECT_TRUE(column == e->name || column.starts_with(e->name + ".")) << column;
    }
    if (e->traits.periodicity != Periodicity::kNone) {
      EXPECT_GE(reg.columns.cols(), 2);
    }
    // Without its parameters: an error that names one of them (or none are needed).
    if (e->parameters.empty()) continue;
    try {
      BuildEffectRegressors({e->name, {}}, s);
    } catch (const std::invalid_argument& error) {
      EXPECT_THAT(error.what(), HasSubstr("effect '" + e->name + "': parameter '"));
    }
  }
}

// A load behind a play whose play is negative, or whose mode is not above 0, is refused naming the parameter.
TEST(EffectRegistry, ALoadBehindAPlayRefusesANegativePlayAndNoMode) {
  const DiagnosisSignals s = Motion();
  const std::map<std::string, double> good = {
      {"backlash", 1e-3}, {"frequency_hz", 20.0}, {"damping_ratio", 0.1}, {"load_damping", 1.0}};
  EXPECT_EQ(BuildEffectRegressors({"backlash_load", good}, s).columns.cols(), 1);
  auto error = [&](const std::string& key, double value) {
    auto parameters = good;
    parameters[key] = value;
    try {
      BuildEffectRegressors({"backlash_load", parameters}, s);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_THAT(error("backlash", -1e-3), HasSubstr("backlash = -0.001 must be >= 0"));
  EXPECT_THAT(error("frequency_hz", 0.0), HasSubstr("frequency_hz"));
}

// The lag of the measurement behind ŷ keeps its sign: a measurement recorded late (a sensor delay, time_delay) is
// +d, a log that leads the model built from the motion (a command that acts later: actuator_lag) is −d; the two
// effects propose on either side.
TEST(EffectProposal, TheDelayEstimateSaysWhichSideLags) {
  for (const double delay : {0.004, -0.004}) {
    SCOPED_TRACE(delay);
    DiagnosisSignals s = Motion();
    s.residual = ShiftedInTime(s.time, s.model_output, delay) - s.model_output;
    const Eigen::MatrixXd base(s.size(), 0);
    CandidateSearch search;
    const ProposalContext context(s, s.residual, base, CatalogueOptions{}, &search);
    EXPECT_NEAR(EstimateModelOutputDelay(context), delay, 0.02 * std::abs(delay));
    CandidateSearch proposed = ProposeCandidateEffects(s, s.residual, base, CatalogueOptions{});
    const auto named = [&](const std::string& effect) {
      return std::any_of(proposed.candidates.begin(), proposed.candidates.end(),
                         [&](const EffectInstance& e) { return e.name == effect; });
    };
    EXPECT_EQ(named("time_delay"), delay > 0.0);
    EXPECT_EQ(named("actuator_lag"), delay < 0.0);
  }
}

TEST(EffectRegistry, UnknownEffectSaysDidYouMean) {
  try {
    LookupEffect("position_periodc");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), StartsWith("unknown effect 'position_periodc'; did you mean 'position_periodic' or "
                                     "'time_periodic'? The "
                                     "catalogue has: constant_offset, viscous_friction, "));
  }
  try {
    BuildEffectRegressors({"cogging", {}}, Motion());
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), StartsWith("unknown effect 'cogging'; the catalogue has: constant_offset, "));
  }
  EXPECT_EQ(EffectRegistry::Global().Find("cogging"), nullptr);
  EXPECT_THROW(EffectPhysics("Stribeck"), std::invalid_argument);
}

// A made-up effect "spring" without its proposal rule.
EffectType SpringWithoutProposal() {
  EffectType t;
  t.name = "spring";
  t.physics = "a force proportional to position";
  t.regressor_formula = "x";
  t.regressors = [](const EffectInstance&, const DiagnosisSignals& s) { return EffectRegressors{s.position, {"spring"}}; };
  return t;
}

TEST(EffectRegistry, RefusesDuplicatesAndIncompleteEffects) {
  EffectRegistry registry;
  EffectType t = SpringWithoutProposal();
  EffectType incomplete = t;
  incomplete.name = "spring2";
  try {
    registry.Add(incomplete);
    FAIL() << "no exception";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "effect 'spring2' registered without its regressors or proposal rule");
  }
  t.propose = [](ProposalContext& c) { c.Propose("spring"); };
  EXPECT_TRUE(registry.Add(t));
  try {
    registry.Add(t);
    FAIL() << "no exception";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "effect 'spring' registered twice");
  }
  EXPECT_EQ(registry.Suggest("sprin"), std::vector<std::string>{"spring"});
}

// The grammar (issue 45): every multiplier crossed with every modulator is held by exactly one registered effect —
// generated, or a hand-written effect of the catalogue in its place — and no registered pair is outside the tables.
TEST(EffectRegistry, EveryPairOfTheTwoTablesIsHeldByExactlyOneEffect) {
  std::map<std::pair<std::string, std::string>, std::vector<std::string>> held;
  for (const EffectType* e : EffectRegistry::Global().Effects()) {
    if (e->multiplier.empty()) continue;
    EXPECT_NE(FindMultiplier(e->multiplier), nullptr) << e->name;
    EXPECT_NE(FindModulator(e->modulator), nullptr) << e->name;
    held[{e->multiplier, e->modulator}].push_back(e->name);
  }
  for (const MultiplierRow& m : Multipliers()) {
    for (const ModulatorRow& mod : Modulators()) {
      const auto it = held.find({m.id, mod.id});
      ASSERT_NE(it, held.end()) << m.id << " × " << mod.id;
      EXPECT_EQ(it->second.size(), 1u) << m.id << " × " << mod.id;
    }
  }
  EXPECT_EQ(held.size(), Multipliers().size() * Modulators().size());
  // The names the catalogue gave before the grammar stay, on their pairs.
  EXPECT_EQ(LookupEffect("friction_ripple").multiplier, "slip");
  EXPECT_EQ(LookupEffect("friction_ripple").modulator, "position_periodic");
  EXPECT_EQ(LookupEffect("mass_change").modulator, "time_step");
  EXPECT_TRUE(LookupEffect("inertia_window").generated);
  EXPECT_FALSE(LookupEffect("mass_change").generated);
}

TEST(EffectRegistry, AHandWrittenEffectTakesTheGeneratedPairsPlaceInEitherOrder) {
  EffectType generated = SpringWithoutProposal();
  generated.propose = [](ProposalContext& c) { c.Propose("spring"); };
  generated.multiplier = "one";
  generated.modulator = "position_smooth";
  generated.generated = true;
  EffectType written = generated;
  written.name = "cable_carrier";
  written.generated = false;
  {
    EffectRegistry registry;
    registry.Add(generated);
    registry.Add(written);
    EXPECT_EQ(registry.Find("spring"), nullptr);
    EXPECT_NE(registry.Find("cable_carrier"), nullptr);
  }
  {
    EffectRegistry registry;
    registry.Add(written);
    registry.Add(generated);
    EXPECT_EQ(registry.Find("spring"), nullptr);
    EXPECT_EQ(registry.Effects().size(), 1u);
  }
  EffectRegistry registry;
  registry.Add(written);
  written.name = "spring_2";
  try {
    registry.Add(written);
    FAIL() << "no exception";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "effects 'cable_carrier' and 'spring_2' are both the pair one × position_smooth");
  }
}

// A new pair reads in its rows' words, with its figures and the column by its name.
TEST(EffectRegistry, APairIsWordedFromItsRows) {
  const std::string words = PairWords(*FindMultiplier("slip"), *FindModulator("column"), {{"column", 0.0}}, 0.031,
                                      "normal_force_N", "m");
  EXPECT_EQ(words, "the Coulomb friction level follows 'normal_force_N': +0.031 per unit of it");
  EXPECT_EQ(PairWords(*FindMultiplier("acceleration"), *FindModulator("time_window"),
                      {{"on_time", 3.0}, {"off_time", 7.5}}, 12.0, "", "m"),
            "the moving mass changes between 3 s and 7.5 s by +12/(m/s²)");
  EXPECT_EQ(PairName(*FindMultiplier("model_force"), *FindModulator("time_warm_up")), "force_constant_warm_up");
}

// docs/diagnosis.md's tables of the grammar are GrammarMarkdown()'s text (`motionblocks grammar` prints it): a row
// added to a table, or a pair taken by a hand-written effect, is in the docs or this fails.
TEST(EffectRegistry, TheDocsHoldTheGrammarAsGenerated) {
  std::ifstream file(std::string(MB_SOURCE_DIR) + "/docs/diagnosis.md");
  ASSERT_TRUE(file) << "cannot read docs/diagnosis.md";
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::string begin = "<!-- grammar:begin (motionblocks grammar) -->\n", end = "<!-- grammar:end -->";
  const auto from = text.find(begin), to = text.find(end);
  ASSERT_NE(from, std::string::npos) << begin;
  ASSERT_NE(to, std::string::npos) << end;
  EXPECT_EQ(text.substr(from + begin.size(), to - from - begin.size()), GrammarMarkdown())
      << "regenerate the region with: build/release/tools/motionblocks grammar";
}

TEST(EffectRegistry, BlockTemplatesAttachToTheirEffectInEitherOrder) {
  EffectRegistry registry;
  EffectType t = SpringWithoutProposal();
  t.propose = [](ProposalContext& c) { c.Propose("spring"); };
  EffectBlockTemplate block;
  block.block_type = "gain";
  block.element_name = "spring";
  block.parameters = [](const DiagnosedEffect&) { return nlohmann::json::object(); };

  EXPECT_TRUE(registry.AddBlockTemplate("spring", block));  // the block file's static initialiser ran first
  EXPECT_EQ(registry.UnclaimedBlockTemplates(), std::vector<std::string>{"spring"});
  EXPECT_TRUE(registry.Add(t));
  EXPECT_TRUE(registry.UnclaimedBlockTemplates().empty());
  ASSERT_TRUE(registry.Get("spring").block.has_value());
  EXPECT_EQ(registry.Get("spring").block->element_name, "spring");
  EXPECT_EQ(::mb::testing::ErrorOf<std::logic_error>([&] { registry.AddBlockTemplate("spring", block); }),
            "effect 'spring' has a block registered twice");

  t.name = "spring2";
  EXPECT_TRUE(registry.Add(t));  // the effect first, its block after
  EXPECT_TRUE(registry.AddBlockTemplate("spring2", block));
  EXPECT_TRUE(registry.Get("spring2").block.has_value());

  block.parameters = nullptr;
  EXPECT_EQ(::mb::testing::ErrorOf<std::logic_error>([&] { registry.AddBlockTemplate("spring3", block); }),
            "the block of effect 'spring3' has no block type, element name or parameters function");
  t.name = "spring4";
  t.block = block;
  EXPECT_EQ(::mb::testing::ErrorOf<std::logic_error>([&] { registry.Add(t); }), "effect 'spring4': register its block with its block");
}

TEST(EffectRegistry, EveryBlockFileTemplateFindsItsEffect) {
  // The blocks (linked here) register the templates of the effects they add (MB_REGISTER_EFFECT_BLOCK).
  EXPECT_TRUE(EffectRegistry::Global().UnclaimedBlockTemplates().empty());
  for (const char* effect : {"constant_offset", "viscous_friction", "coulomb_friction", "stribeck_friction",
                             "mass_mismatch", "position_periodic", "velocity_dependent_ripple", "time_periodic",
                             "time_delay", "quantization", "resonance", "position_dependent_force",
                             "regularized_coulomb_friction", "backlash", "friction_drift", "friction_warm_up",
                             "drive_saturation", "drive_voltage_limit", "quadratic_drag", "inertia_ripple",
                             "local_force_constant", "force_constant_along_travel", "column_force_constant"}) {
    EXPECT_TRUE(LookupEffect(effect).block.has_value()) << effect;
  }
  EXPECT_FALSE(LookupEffect("presliding_friction").block.has_value());  // added by hand (the report says so)
}

TEST(EffectRegistry, RecordSpecificParametersComeFromTheBlockTemplates) {
  // The ripple blocks' encoder zero belongs to the record; a gain's parameters to the machine.
  EXPECT_EQ(RecordSpecificParameters(LookupEffect("position_periodic").block->block_type),
            std::vector<std::string>{"position_offset"});
  EXPECT_TRUE(RecordSpecificParameters("gain").empty());
  EXPECT_TRUE(RecordSpecificParameters("no_such_block").empty());
}

// A parameter in words with the registry's unit (parameter_text.h): what the diagnosis text and the compare report's
// table both show.
TEST(ParameterText, UnitsFromTheRegistryInTheReadersUnitsAndCountsAsIntegers) {
  EXPECT_EQ(EffectParameterUnit("position_periodic", "period"), "m");
  EXPECT_EQ(EffectParameterUnit("stribeck_friction", "stribeck_velocity"), "m/s");
  EXPECT_EQ(EffectParameterUnit("time_periodic", "harmonics"), "");
  EXPECT_EQ(EffectParameterUnit("no_such_effect", "period"), "");
  EXPECT_EQ(FormatParameterValue(0.0025034, "m", "m"), "2.503 mm");
  EXPECT_EQ(FormatParameterValue(0.02827, "m/s", "m"), "28.27 mm/s");
  EXPECT_EQ(FormatParameterValue(0.5, "m", "rad"), "0.5 rad");  // a rotary axis keeps its unit
  EXPECT_EQ(FormatParameterValue(0.5, "m/s", "rad"), "0.5 rad/s");
  EXPECT_EQ(FormatParameterValue(0.004092, "s", "m"), "0.004092 s");
  EXPECT_EQ(FormatParameterValue(2.0, "", "m"), "2");  // harmonics, not 2.0
  EXPECT_EQ(FormatParameterValue(116.8, "", "m"), "116.8");
}

}  // namespace
}  // namespace mb
