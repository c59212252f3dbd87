// Runs that must stop instead of returning nonsense or hanging (issue 11): NaN/Inf at the step it appears,
// steps longer than the run or too small to advance time, runs beyond the step limit, a Zeno loop of events,
// and JSON nested too deeply to parse safely.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <fmt/format.h>
#include <unistd.h>

#include "engine/json_limits.h"
#include "engine/numerical_error.h"
#include "engine/output_file.h"
#include "tests/engine/test_util.h"

namespace mb {
namespace {

using testing::Build;
using testing::Connect;
using nlohmann::json;
using ::testing::HasSubstr;

// ẋ = a·x, x(0) = 1: with a = 1e308 the state overflows to Inf in the first step.
json Growth(const json& solver, double a, const json& experiment) {
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", experiment},
          {"solver", solver},
          {"elements",
           {{{"name", "x"}, {"type", "integrator"}, {"parameters", {{"initial_condition", 1.0}}}},
            {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", a}}}}}},
          {"connections", {Connect("x.y", "k.u"), Connect("k.y", "x.u")}},
          {"log", {"x.y"}}};
}

const json kOneSecond = {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 0.01}};

template <class Error>
std::string MessageOf(const Diagram& d, SimulationLimits limits = {}) {
  try {
    Simulator(d, limits).Run();
  } catch (const Error& e) {
    return e.what();
  }
  return "no exception";
}

TEST(RuntimeLimitsTest, DivergenceStopsAtTheStepWithTheBlockAndTime) {
  // 1e308 · x overflows within the first step: an RK4 stage of the integrator's output is already Inf.
  const std::string rk4 = MessageOf<NumericalError>(Build(Growth({{"type", "rk4"}, {"step", 1e-3}}, 1e308, kOneSecond)));
  EXPECT_EQ(rk4, "rk4 solver: block 'x' output 'y' is inf after the step to t = 0.001 s (step 0.001 s). The model "
                 "diverged or a block computed an invalid value: check that block's parameters and inputs, or try a "
                 "smaller solver.step or the cvode solver");
  // A slower blow-up (x ← 3x per Euler step) is caught at the major step where the gain's output first overflows
  // (2000·3^n > 1.8e308 at n = 640), long before the end of the run.
  const std::string slow = MessageOf<NumericalError>(Build(Growth({{"type", "euler"}, {"step", 1e-3}}, 2000.0,
                                                                   kOneSecond)));
  EXPECT_THAT(slow, HasSubstr("test: at t = 0.64 s block 'k' output 'y' is inf (the first NaN/Inf, in execution "
                              "order)"));
}

TEST(RuntimeLimitsTest, CvodeDivergenceIsANumericalError) {
  const std::string m = MessageOf<NumericalError>(Build(Growth({{"type", "cvode"}}, 1e308, kOneSecond)));
  EXPECT_THAT(m, HasSubstr("CVODE failed at t = 0 s: "));
  EXPECT_THAT(m, HasSubstr("; NaN/Inf at t = 0 s: block 'x' output 'y' is "));  // CVODE's trial state: Inf or NaN
}

TEST(RuntimeLimitsTest, NonFiniteOutputAtStartNamesTheBlock) {
  const json j = {{"schemaVersion", "1.0"},
                  {"defaultExperiment", kOneSecond},
                  {"elements",
                   {{{"name", "c"}, {"type", "constant"}, {"parameters", {{"value", 10.0}}}},
                    {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", 1e308}}}}}},
                  {"connections", {Connect("c.y", "k.u")}},
                  {"log", {"k.y"}}};
  EXPECT_EQ(MessageOf<NumericalError>(Build(j)),
            "test: at t = 0 s block 'k' output 'y' is inf (the first NaN/Inf, in execution order). The model "
            "diverged or the block computed an invalid value: check its parameters and inputs");
}

TEST(RuntimeLimitsTest, StepLongerThanTheRunIsRefusedWithTheFix) {
  const json ex = {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 5.0}};
  EXPECT_EQ(MessageOf<std::invalid_argument>(Build(Growth({{"type", "rk4"}, {"step", 1e-3}}, -1.0, ex))),
            "test: defaultExperiment.stepSize (5 s) is longer than the run (1 s, from startTime 0 s to stopTime 1 s): "
            "the run would log only its start. Make it at most 1 s, or make stopTime later");
  EXPECT_THAT(MessageOf<std::invalid_argument>(Build(Growth({{"type", "rk4"}, {"step", 2.0}}, -1.0, kOneSecond))),
              HasSubstr("test: solver.step (2 s) is longer than the run (1 s"));
  json discrete = {{"schemaVersion", "1.0"},
                   {"defaultExperiment", {{"stopTime", 1.0}}},
                   {"elements",
                    {{{"name", "c"}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}},
                     {{"name", "d"}, {"type", "unit_delay"}, {"sampleTime", {3.0, 0.0}}}}},
                   {"connections", {Connect("c.y", "d.u")}},
                   {"log", {"d.y"}}};
  EXPECT_THAT(MessageOf<std::invalid_argument>(Build(discrete)),
              HasSubstr("test: the sampleTime of element 'd' (3 s) is longer than the run (1 s"));
}

TEST(RuntimeLimitsTest, AStepThatCannotAdvanceTimeIsRefused) {
  const json ex = {{"startTime", 1e17}, {"stopTime", 1e17 + 1e6}, {"stepSize", 1.0}};
  EXPECT_EQ(MessageOf<std::invalid_argument>(Build(Growth({{"type", "cvode"}}, -1.0, ex))),
            "test: defaultExperiment.stepSize (1 s) vanishes next to the run's times (t = 1.00000000001e+17 s): t + 1 "
            "== t in double precision, so time could never advance. Use a larger step, or start the run nearer t = 0");
  const json tiny = {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 1e-300}};
  EXPECT_THAT(MessageOf<std::invalid_argument>(Build(Growth({{"type", "cvode"}}, -1.0, tiny))),
              HasSubstr("test: defaultExperiment.stepSize (1e-300 s) vanishes next to the run's times (t = 1 s)"));
}

TEST(RuntimeLimitsTest, RunsBeyondTheStepLimitAreRefusedBeforeTheyStart) {
  const json long_run = {{"startTime", 0.0}, {"stopTime", 1e9}, {"stepSize", 0.01}};
  EXPECT_EQ(MessageOf<std::invalid_argument>(Build(Growth({{"type", "rk4"}, {"step", 1e-3}}, -1.0, long_run))),
            "test: the run from 0 s to 1000000000 s in steps of 0.001 s (solver.step) takes about 1e+12 steps, more "
            "than the limit of 1e+08. Shorten the run (defaultExperiment.stopTime), enlarge the step, or raise the "
            "limit with --max-steps N");
  // The log counts too: 1e4 steps but 2e4 values (two logged signals) against a limit of 1.5e4.
  json two_signals = Growth({{"type", "cvode"}}, -1.0, {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 1e-4}});
  two_signals["log"] = {"x.y", "k.y"};
  SimulationLimits small;
  small.max_steps = 1.5e4;
  EXPECT_EQ(MessageOf<std::invalid_argument>(Build(two_signals), small),
            "test: the log would hold about 2e+04 values (1e+04 samples every 0.0001 s × 2 signals, 0.16 MB), more "
            "than the limit of 1.5e+04. Log fewer signals, a larger defaultExperiment.stepSize or a shorter run, or "
            "raise the limit with --max-steps N");
  small.max_steps = 3e4;  // raised: the same run goes
  EXPECT_EQ(MessageOf<std::invalid_argument>(Build(two_signals), small), "no exception");
}

// The same run as above streamed to disk (`run` does): the file gets every sample, memory keeps at most 100, the
// metrics are those of the whole log, and the log-size limit that refused it in memory no longer applies.
TEST(RuntimeLimitsTest, AStreamedLogWritesEverySampleWithinASmallMemoryBound) {
  json two_signals = Growth({{"type", "cvode"}}, -1.0, {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 1e-4}});
  two_signals["log"] = {"x.y", "k.y"};
  two_signals["metrics"] = {{{"name", "x_rms"}, {"type", "rmse"}, {"signal", "x.y"}},
                            {{"name", "x_final"}, {"type", "final"}, {"signal", "x.y"}},
                            {{"name", "sum_max"}, {"type", "max_abs"}, {"signal", "x.y"}, {"reference", "k.y"}}};
  const Diagram d = Build(two_signals);
  SimulationLimits raised;
  raised.max_steps = 3e4;
  const SimulationResult in_memory = Simulator(d, raised).Run();  // the reference
  SimulationLimits small;
  small.max_steps = 1.5e4;  // refuses the log in memory (above)
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("mb_streamed_log_" + std::to_string(::getpid()) + ".csv");
  Simulator streamed(d, small);
  CsvLogFile file(path);
  streamed.StreamLogTo(&file, 100);
  const SimulationResult result = streamed.Run();
  file.Commit();
  EXPECT_EQ(streamed.logged_samples(), static_cast<long long>(in_memory.log.time.size()));
  EXPECT_LE(result.log.time.size(), 102u);
  EXPECT_GE(result.log.time.size(), 50u);
  EXPECT_EQ(result.log.time.front(), 0.0);
  for (const auto& [name, value] : in_memory.metrics) EXPECT_DOUBLE_EQ(result.metrics.at(name), value) << name;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "time_s,x.y,k.y");
  std::size_t rows = 0;
  std::string last;
  while (std::getline(in, line)) {
    ++rows;
    last = line;
  }
  EXPECT_EQ(rows, in_memory.log.time.size());
  const std::size_t n = in_memory.log.time.size() - 1;
  EXPECT_EQ(last, fmt::format("{},{},{}", in_memory.log.time[n], in_memory.log.columns[0][n],
                              in_memory.log.columns[1][n]));  // shortest round trip, as WriteSignalLog
  std::filesystem::remove(path);
}

// The in-memory copy of a streamed log is its envelope: a 37 Hz sine sampled at 10 kHz and kept in 100 rows still
// reaches its exact extremes (an even thinning, every 201st sample, would miss them) and stays inside them.
TEST(RuntimeLimitsTest, AStreamedLogKeepsItsEnvelopeInMemory) {
  const json sine = {{"schemaVersion", "1.0"},
                     {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 1e-4}}},
                     {"elements",
                      {{{"name", "s"}, {"type", "sine"}, {"parameters", {{"amplitude", 2.0}, {"frequency_hz", 37.0}}}}}},
                     {"log", {"s.y"}}};
  const Diagram d = Build(sine);
  const SimulationResult full = Simulator(d).Run();
  const auto& y = full.log.columns[0];
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("mb_envelope_log_" + std::to_string(::getpid()) + ".csv");
  Simulator streamed(d);
  CsvLogFile file(path);
  streamed.StreamLogTo(&file, 100);
  const SimulationResult kept = streamed.Run();
  file.Commit();
  std::filesystem::remove(path);
  const auto& e = kept.log.columns[0];
  ASSERT_LE(e.size(), 102u);
  ASSERT_GE(e.size(), 90u);
  EXPECT_EQ(*std::max_element(e.begin(), e.end()), *std::max_element(y.begin(), y.end()));
  EXPECT_EQ(*std::min_element(e.begin(), e.end()), *std::min_element(y.begin(), y.end()));
  EXPECT_EQ(kept.log.time.front(), 0.0);
  EXPECT_EQ(kept.log.time.back(), full.log.time.back());
  for (std::size_t i = 1; i < kept.log.time.size(); ++i) EXPECT_LE(kept.log.time[i - 1], kept.log.time[i]) << i;
}

TEST(RuntimeLimitsTest, DefaultLimitsCanBeRaised) {
  const SimulationLimits before = DefaultSimulationLimits();
  SimulationLimits raised = before;
  raised.max_steps = 1e12;
  SetDefaultSimulationLimits(raised);
  EXPECT_EQ(DefaultSimulationLimits().max_steps, 1e12);
  SetDefaultSimulationLimits(before);
  EXPECT_EQ(DefaultSimulationLimits().max_steps, 1e8);
}

// NaN would turn the step limit off (every "steps > limit" is false): refused, as infinity and 0 on the command line.
TEST(RuntimeLimitsTest, ANanOrInfiniteStepLimitIsRefused) {
  const SimulationLimits before = DefaultSimulationLimits();
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), 0.0, 1e14}) {
    SimulationLimits limits = before;
    limits.max_steps = bad;
    try {
      SetDefaultSimulationLimits(limits);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()),
                fmt::format("--max-steps {}: the step limit must be a finite number in [1, 1e+13] (default 1e+08); "
                            "give the number of steps a run may take",
                            bad));
    }
  }
  EXPECT_EQ(DefaultSimulationLimits().max_steps, before.max_steps);  // unchanged
  SimulationLimits nan_limit;
  nan_limit.max_steps = std::nan("");
  Diagram d;
  EXPECT_THROW(Simulator(d, nan_limit), std::invalid_argument);
}

// A body at rest under 5 N against 10 N of Coulomb friction with stick_model "none": each located v = 0 flips
// the slip direction, and the next step crosses back (Zeno). The run must stop and name the friction block.
TEST(RuntimeLimitsTest, ZenoLoopOfEventsIsBoundedAndNamesTheBlock) {
  const json j = {
      {"schemaVersion", "1.0"},
      {"defaultExperiment", {{"stopTime", 1.0}, {"stepSize", 0.01}}},
      {"solver", {{"type", "cvode"}}},
      {"elements",
       {{{"name", "force"}, {"type", "constant"}, {"parameters", {{"value", 5.0}}}},
        {{"name", "net"}, {"type", "sum"}, {"parameters", {{"signs", "+-"}}}},
        {{"name", "friction"}, {"type", "friction"}, {"parameters", {{"coulomb", 10.0}, {"stick_model", "none"}}}},
        {{"name", "body"}, {"type", "rigid_body"}, {"parameters", {{"mass", 1.0}}}}}},
      {"connections",
       {Connect("force.y", "net.u1"), Connect("friction.f", "net.u2"), Connect("net.y", "body.f"),
        Connect("body.v", "friction.v")}},
      {"log", {"body.v"}}};
  SimulationLimits limits;
  limits.max_events_per_major_step = 200;  // fast under ASan
  const std::string m = MessageOf<NumericalError>(Build(j), limits);
  // It slides away from rest in the first 20 ms, then every step crosses v = 0 back and forth.
  EXPECT_THAT(m, HasSubstr("200 zero-crossing events between t = 0.02 s and t = 0.02 s without reaching the next "
                           "major step at 0.03 s: "));
  EXPECT_THAT(m, HasSubstr("the zero crossing 0 of block 'friction' fires again and again (a Zeno loop"));
}

TEST(JsonLimitsTest, DeepNestingIsRefusedBeforeParsing) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  try {
    ParseJsonLimited(deep, "deep.json");
    FAIL() << "no exception";
  } catch (const JsonDepthError& e) {
    EXPECT_EQ(std::string(e.what()),
              "deep.json: JSON nested deeper than 256 levels of arrays/objects; refusing to read it (real diagrams, "
              "sweeps and models nest fewer than 20: is the file generated wrongly?)");
  }
  const std::string ok = std::string(256, '[') + std::string(256, ']');
  EXPECT_TRUE(ParseJsonLimited(ok, "ok.json").is_array());
  EXPECT_THROW(ParseJsonLimited(std::string(257, '[') + std::string(257, ']'), "x"), JsonDepthError);
  EXPECT_THROW(ParseJsonLimited(std::string("{\"a\": [1,"), "x"), nlohmann::json::parse_error);  // syntax: as before
  EXPECT_EQ(ParseJsonLimited(std::string("// c\n{\"a\": 1}"), "x", /*ignore_comments=*/true)["a"], 1);
}

TEST(JsonLimitsTest, DiagramFilesGoThroughTheDepthCheck) {
  const std::string path = ::testing::TempDir() + "deep_diagram.json";
  {
    std::ofstream out(path);
    out << "{\"elements\": " << std::string(5000, '[') << std::string(5000, ']') << "}";
  }
  EXPECT_THROW(ReadDiagramJson(path), JsonDepthError);
}

// Issue 41: nlohmann's parser takes a NUL byte for the end of the input, so a diagram padded with zeros after its
// closing brace (a truncated copy, a preallocated file) was read as whole; and comments, which no JSON reader but
// this one took, are refused with a hint.
TEST(JsonLimitsTest, ANulByteOrACommentInADiagramIsRefusedWithItsPlace) {
  const std::string path = ::testing::TempDir() + "padded_diagram.json";
  const std::string diagram = R"({"schemaVersion": "1.0", "elements": [{"name": "c", "type": "constant"}]})";
  const auto error = [&](const std::string& text) -> std::string {
    std::ofstream(path, std::ios::binary) << text;
    try {
      ReadDiagramJson(path);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error(diagram + "\n" + std::string(3, '\0')),
            path + ": not valid JSON: parse error at byte 75: a NUL byte at line 2, column 1 (and 2 more to the end of "
                   "the file): no JSON text holds one (is the file truncated, padded with zeros or binary?); restore "
                   "the file");
  EXPECT_THAT(error(std::string("{\"schemaVersion\": \"1.0\",") + '\0' + " \"elements\": []}"),
              HasSubstr("a NUL byte at line 1, column 25: no JSON text holds one"));
  EXPECT_THAT(error("// a comment\n" + diagram),
              HasSubstr("; comments (// or /* */) are not JSON: remove them (a diagram keeps its notes in "
                        "\"description\" or \"notes\")"));
  EXPECT_THAT(error(diagram.substr(0, 25) + "/* a comment */" + diagram.substr(25)),
              HasSubstr("comments (// or /* */) are not JSON"));
  EXPECT_EQ(error(diagram), "no error");
  EXPECT_THROW(ParseJsonLimited(std::string("{}\0\0", 4), "x"), nlohmann::json::parse_error);  // GP models too
}

// Issue 41: a file of a million elements is refused after reading a fifth of it, before it is parsed.
TEST(JsonLimitsTest, ADiagramFileOfTooManyElementsIsRefusedBeforeItIsParsed) {
  const std::string path = ::testing::TempDir() + "many_elements.json";
  {
    std::ofstream out(path);
    out << R"({"schemaVersion": "1.0", "notes": "x", "elements": [)";
    for (std::size_t i = 0; i < 2 * kMaxDiagramElements; ++i) {
      out << (i ? "," : "") << R"({"name": "c)" << i << R"(", "type": "constant"})";
    }
    out << "], \"connections\": [}";  // a syntax error at the end: never reached
  }
  try {
    ReadDiagramJson(path);
    FAIL() << "no exception";
  } catch (const DiagramError& e) {
    EXPECT_THAT(e.what(), HasSubstr(fmt::format("/elements: {} elements or more, more than the {} a diagram may hold",
                                                kMaxDiagramElements + 1, kMaxDiagramElements)));
  }
}

}  // namespace
}  // namespace mb
