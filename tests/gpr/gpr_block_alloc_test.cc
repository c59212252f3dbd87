// The gpr block's CalcOutput allocates nothing: a diagram with the block fed by two sources, no
// logged signals, and a counting global operator new around Simulator::AdvanceTo after Initialize.
// The same diagram without the gpr block measures the engine's own allocations in AdvanceTo.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_io.h"
#include "tests/alloc_counter.h"
#include "tests/gpr/synthetic_data.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json Connect(const std::string& se, const std::string& sc, const std::string& ee, const std::string& ec) {
  return {{"startElement", se}, {"startConnector", sc}, {"endElement", ee}, {"endConnector", ec}};
}

// Two sine sources; with `with_gpr` a gpr block (std output too, discrete or inherited) reads them; with `online`
// it learns online from a third sine.
json AllocDiagram(bool with_gpr, const json& sample_time, bool online = false) {
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 1e-3}}},
            {"elements",
             {{{"name", "pos"}, {"type", "sine"},
               {"parameters", {{"amplitude", 0.15}, {"frequency_hz", 2.0}, {"bias", 0.2}}}},
              {{"name", "vel"}, {"type", "sine"},
               {"parameters", {{"amplitude", 0.6}, {"frequency_hz", 3.0}, {"bias", 0.2}}}}}},
            {"connections", json::array()}};
  if (with_gpr) {
    json gpr = {{"name", "dhat"}, {"type", "gpr"}, {"parameters", {{"model", "model.json"}, {"output_std", true}}}};
    if (!sample_time.is_null()) gpr["sampleTime"] = sample_time;
    j["elements"].push_back(gpr);
    j["connections"] = {Connect("pos", "y", "dhat", "x"), Connect("vel", "y", "dhat", "xdot")};
    if (online) {
      j["elements"].back()["parameters"]["learning"] = "online";
      j["elements"].back()["parameters"]["forgetting"] = 0.999;
      j["elements"].push_back({{"name", "dist"}, {"type", "sine"}, {"parameters", {{"amplitude", 0.3}}}});
      j["connections"].push_back(Connect("dist", "y", "dhat", "d"));
    }
  }
  return j;
}

class GprBlockAllocation : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: ctest runs the tests of this fixture as parallel processes, and one's TearDown must not
    // remove the model another is loading.
    dir_ = fs::temp_directory_path() /
           ("mb_gpr_block_alloc_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
    const auto data = testing::ConstantVelocityScans(0.1, 0.325, 15, 0.02, 51);
    GprFitOptions options;
    options.restarts = 0;
    SaveGprModel(FitGpr(data.x, data.xdot, data.d, options), dir_ / "model.json");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Allocations during AdvanceTo(stop) after Initialize; the final outputs for a check.
  long AdvanceAllocations(const json& j, double* mean, double* x, double* v) const {
    const Diagram diagram = BuildDiagram(j, dir_, "alloc.json");
    Simulator sim(diagram);
    sim.Initialize();
    const long before = ::mb::testing::AllocationCount();
    sim.AdvanceTo(diagram.experiment().stop_time);
    const long count = ::mb::testing::AllocationCount() - before;
    *x = sim.SignalValue(diagram.ResolveSignal("pos.y"));
    *v = sim.SignalValue(diagram.ResolveSignal("vel.y"));
    *mean = diagram.blocks().size() > 2 ? sim.SignalValue(diagram.ResolveSignal("dhat.mean")) : 0.0;
    return count;
  }

  fs::path dir_;
};

TEST_F(GprBlockAllocation, AdvanceToAllocatesNothing) {
  const long before_probe = ::mb::testing::AllocationCount();
  void* probe = ::operator new(16);  // the counter works
  const long after_probe = ::mb::testing::AllocationCount();
  ::operator delete(probe);
  ASSERT_EQ(after_probe, before_probe + 1);

  double mean = 0.0, x = 0.0, v = 0.0;
  // The engine alone (sources only): the baseline the block adds to.
  EXPECT_EQ(AdvanceAllocations(AllocDiagram(false, nullptr), &mean, &x, &v), 0) << "the engine allocates";

  const GprModel model = LoadGprModel(dir_ / "model.json");
  for (const json& sample_time : {json(nullptr), json{1e-3, 0.0}}) {
    EXPECT_EQ(AdvanceAllocations(AllocDiagram(true, sample_time), &mean, &x, &v), 0)
        << "sampleTime " << sample_time.dump();
    // The block did run during AdvanceTo: its output is the prediction at the final inputs.
    EXPECT_EQ(mean, model.PredictPosteriorMean(x, v)) << "sampleTime " << sample_time.dump();
    EXPECT_NEAR(x, 0.2, 1e-9);  // sin(2π·2·1) = 0 at the stop time
  }
  // Learning online: 1000 rank-one updates of the posterior in the discrete state, no allocation.
  EXPECT_EQ(AdvanceAllocations(AllocDiagram(true, json{1e-3, 0.0}, true), &mean, &x, &v), 0) << "learning online";
  EXPECT_NE(mean, model.PredictPosteriorMean(x, v));  // it learned
}

// The adaptive mass feedforward (blocks/adaptive_mass_feedforward.h): its recursive least squares and the two
// Q-filters run in the discrete state, allocation-free.
TEST_F(GprBlockAllocation, AdaptiveMassFeedforwardAllocatesNothing) {
  json j = AllocDiagram(false, nullptr);
  j["elements"].push_back({{"name", "mass_ff"},
                           {"type", "adaptive_mass_feedforward"},
                           {"sampleTime", {1e-3, 0.0}},
                           {"parameters", {{"forgetting", 0.999}}}});
  j["connections"] = {Connect("pos", "y", "mass_ff", "acceleration"), Connect("pos", "y", "mass_ff", "x"),
                      Connect("vel", "y", "mass_ff", "d_hat")};
  const Diagram diagram = BuildDiagram(j, dir_, "alloc.json");
  Simulator sim(diagram);
  sim.Initialize();
  const long before = ::mb::testing::AllocationCount();
  sim.AdvanceTo(diagram.experiment().stop_time);
  EXPECT_EQ(::mb::testing::AllocationCount() - before, 0);
  EXPECT_NE(sim.SignalValue(diagram.ResolveSignal("mass_ff.mass")), 0.0);  // it adapted
}

}  // namespace
}  // namespace mb
