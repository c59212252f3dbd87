// The gpr block in a diagram: outputs exactly GprModel's posterior mean and std (ẋ clamped outside
// the trained range), holds between hits when discrete, resolves the model file against the
// diagram's folder, and names the element and the file when the model cannot be loaded.
#include "blocks/gpr.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/gpr_recursive.h"
#include "tests/gpr/synthetic_data.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;

json Connect(const std::string& se, const std::string& sc, const std::string& ee, const std::string& ec) {
  return {{"startElement", se}, {"startConnector", sc}, {"endElement", ee}, {"endConnector", ec}};
}

// x(t) sweeps 0.05…0.35 m (beyond the trained window 0.1…0.325 m), ẋ(t) sweeps −0.4…0.8 m/s (beyond
// the trained 0.05…0.5 m/s on both sides) so that both extrapolation rules are exercised.
json GprDiagram(const json& gpr_element) {
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.5}, {"stepSize", 1e-3}}},
          {"elements",
           {{{"name", "pos"}, {"type", "sine"},
             {"parameters", {{"amplitude", 0.15}, {"frequency_hz", 2.0}, {"bias", 0.2}}}},
            {{"name", "vel"}, {"type", "sine"},
             {"parameters", {{"amplitude", 0.6}, {"frequency_hz", 3.0}, {"phase", 0.3}, {"bias", 0.2}}}},
            gpr_element}},
          {"connections", {Connect("pos", "y", "dhat", "x"), Connect("vel", "y", "dhat", "xdot")}},
          {"log", {"pos.y", "vel.y", "dhat.mean"}}};
}

class GprBlock : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto data = testing::ConstantVelocityScans(0.1, 0.325, 15, 0.02, 41);
    GprFitOptions options;
    options.restarts = 0;
    model_ = new GprModel(FitGpr(data.x, data.xdot, data.d, options));
  }
  static void TearDownTestSuite() { delete model_; }
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_gpr_block_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
    SaveGprModel(*model_, dir_ / "model.json");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string BuildError(const json& j) const {
    try {
      BuildDiagram(j, dir_, "gpr_test.json");
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  }

  static GprModel* model_;
  fs::path dir_;
};
GprModel* GprBlock::model_ = nullptr;

TEST_F(GprBlock, DiagramOutputsExactlyThePosteriorMeanAndStd) {
  json j = GprDiagram({{"name", "dhat"}, {"type", "gpr"},
                    {"parameters", {{"model", "model.json"}, {"output_std", true}}}});
  j["log"].push_back("dhat.std");
  const Diagram diagram = BuildDiagram(j, dir_, "gpr_test.json");  // relative to the diagram's folder
  Simulator sim(diagram);
  const SimulationResult r = sim.Run();
  const auto& x = r.log.Column("pos.y");
  const auto& v = r.log.Column("vel.y");
  const auto& mean = r.log.Column("dhat.mean");
  const auto& sd = r.log.Column("dhat.std");
  ASSERT_EQ(mean.size(), 501u);
  const GprRange trained = model_->xdot_range();
  int below = 0, above = 0;
  for (std::size_t k = 0; k < mean.size(); ++k) {
    ASSERT_EQ(mean[k], model_->PredictPosteriorMean(x[k], v[k])) << "t = " << r.log.time[k];
    double expected_sd = -1.0;
    model_->Predict(x[k], v[k], nullptr, &expected_sd);
    ASSERT_EQ(sd[k], expected_sd) << "t = " << r.log.time[k];
    EXPECT_GT(sd[k], 0.0);
    if (v[k] < trained.min || v[k] > trained.max) {
      // Outside the trained velocity range the block gives the value at the range's boundary.
      const double clamped = std::clamp(v[k], trained.min, trained.max);
      EXPECT_EQ(mean[k], model_->PredictPosteriorMean(x[k], clamped));
      (v[k] < trained.min ? below : above)++;
    }
  }
  EXPECT_GT(below, 10);
  EXPECT_GT(above, 10);
  // Sanity against the truth inside the trained ranges (the model is a model of something).
  EXPECT_NEAR(model_->PredictPosteriorMean(0.2, 0.3), testing::TrueDisturbance(0.2, 0.3), 0.05);
}

TEST_F(GprBlock, ConfidenceWeightingScalesTheMeanByTheModelsWeight) {
  const Diagram diagram = BuildDiagram(
      GprDiagram({{"name", "dhat"}, {"type", "gpr"},
                  {"parameters", {{"model", "model.json"}, {"confidence_weighting", true}}}}),
      dir_, "gpr_test.json");
  const SimulationResult r = Simulator(diagram).Run();
  const auto& x = r.log.Column("pos.y");
  const auto& v = r.log.Column("vel.y");
  const auto& mean = r.log.Column("dhat.mean");
  for (std::size_t k = 0; k < mean.size(); ++k) {
    double weight = -1.0;
    ASSERT_EQ(mean[k], model_->PredictConfidenceWeightedMean(x[k], v[k], &weight)) << "t = " << r.log.time[k];
    const double unweighted = model_->PredictPosteriorMean(x[k], v[k]);  // same sum, other summation order
    ASSERT_NEAR(mean[k], weight * unweighted, 1e-12 * (1.0 + std::abs(unweighted))) << "t = " << r.log.time[k];
    ASSERT_GT(weight, 0.0);
    ASSERT_LT(weight, 1.0);  // σ² > 0 everywhere: never full trust
  }
}

TEST_F(GprBlock, StdOutputOnlyWhenRequested) {
  const Diagram diagram =
      BuildDiagram(GprDiagram({{"name", "dhat"}, {"type", "gpr"}, {"parameters", {{"model", "model.json"}}}}), dir_,
                   "gpr_test.json");
  const auto& block = dynamic_cast<const Gpr&>(*diagram.blocks().at(2));
  ASSERT_EQ(block.output_ports().size(), 1u);
  EXPECT_EQ(block.output_ports()[0].name, "mean");
  EXPECT_EQ(block.input_ports()[0].unit, "m");
  EXPECT_EQ(block.input_ports()[1].unit, "m/s");
  EXPECT_EQ(block.sample_time().kind, SampleTime::Kind::kInherited);
  EXPECT_EQ(block.model().feature_count(), model_->feature_count());

  json j = GprDiagram({{"name", "dhat"}, {"type", "gpr"}, {"parameters", {{"model", "model.json"}}}});
  j["log"].push_back("dhat.std");
  EXPECT_THAT(BuildError(j), HasSubstr("dhat.std"));
}

TEST_F(GprBlock, DiscreteBlockComputesAtHitsAndHolds) {
  const double ts = 0.01;
  const Diagram diagram = BuildDiagram(GprDiagram({{"name", "dhat"}, {"type", "gpr"}, {"sampleTime", {ts, 0.0}},
                                                {"parameters", {{"model", "model.json"}}}}),
                                       dir_, "gpr_test.json");
  EXPECT_TRUE(diagram.blocks().at(2)->sample_time().is_discrete());
  Simulator sim(diagram);
  const SimulationResult r = sim.Run();
  const auto& x = r.log.Column("pos.y");
  const auto& v = r.log.Column("vel.y");
  const auto& mean = r.log.Column("dhat.mean");
  ASSERT_EQ(mean.size(), 501u);
  // Log step 1 ms, Ts = 10 ms: row k holds the value computed at the last hit, row 10·floor(k/10).
  for (std::size_t k = 0; k < mean.size(); ++k) {
    const std::size_t hit = k - k % 10;
    ASSERT_EQ(mean[k], model_->PredictPosteriorMean(x[hit], v[hit])) << "t = " << r.log.time[k];
  }
  EXPECT_NE(mean[10], mean[9]);  // it does change at a hit
}

// learning "online": at each hit the block outputs the recursive posterior's mean after the updates of the earlier
// hits (every `update_every`-th), from the prior or from the model file — the same sequence replayed through
// GprRecursivePosterior gives the same outputs.
TEST_F(GprBlock, OnlineLearningIsTheRecursivePosteriorReplayed) {
  for (const char* learn_from : {"prior", "model"}) {
    SCOPED_TRACE(learn_from);
    json j = GprDiagram({{"name", "dhat"},
                         {"type", "gpr"},
                         {"sampleTime", {1e-3, 0.0}},
                         {"parameters",
                          {{"model", "model.json"},
                           {"learning", "online"},
                           {"learn_from", learn_from},
                           {"forgetting", 0.999},
                           {"update_every", 3},
                           {"output_std", true}}}});
    j["elements"].push_back({{"name", "dist"}, {"type", "sine"},
                             {"parameters", {{"amplitude", 0.4}, {"frequency_hz", 5.0}, {"bias", 0.1}}}});
    j["connections"].push_back(Connect("dist", "y", "dhat", "d"));
    j["log"].push_back("dist.y");
    j["log"].push_back("dhat.std");
    const SimulationResult r = Simulator(BuildDiagram(j, dir_, "gpr_test.json")).Run();
    const auto& x = r.log.Column("pos.y");
    const auto& v = r.log.Column("vel.y");
    const auto& d = r.log.Column("dist.y");
    const auto& mean = r.log.Column("dhat.mean");
    const auto& sd = r.log.Column("dhat.std");
    ASSERT_EQ(mean.size(), 501u);
    GprRecursivePosterior replay(*model_, 0.999, std::string(learn_from) == "prior");
    for (std::size_t k = 0; k < mean.size(); ++k) {
      const double expected = replay.PredictPosteriorMean(x[k], v[k]);
      ASSERT_NEAR(mean[k], expected, 1e-9 * (1.0 + std::abs(expected))) << "t = " << r.log.time[k];
      double expected_sd = -1.0;
      model_->Predict(replay.posterior(), x[k], v[k], nullptr, &expected_sd);
      ASSERT_NEAR(sd[k], expected_sd, 1e-9) << "t = " << r.log.time[k];
      if ((k + 1) % 3 == 0) replay.Update(x[k], v[k], d[k]);
    }
    EXPECT_EQ(replay.updates(), 167);
    // It did learn: the output moved away from where it started.
    EXPECT_GT(std::abs(mean.back() - GprRecursivePosterior(*model_, 1.0, std::string(learn_from) == "prior")
                                         .PredictPosteriorMean(x.back(), v.back())),
              1e-3);
  }
}

TEST_F(GprBlock, OnlineLearningNeedsASampleTimeAndDoesNotFeedThrough) {
  const json element = {{"name", "dhat"}, {"type", "gpr"},
                        {"parameters", {{"model", "model.json"}, {"learning", "online"}}}};
  EXPECT_THAT(BuildError(GprDiagram(element)),
              HasSubstr("learning \"online\" needs a sampleTime [Ts, 0]: the posterior is updated at the block's "
                        "sample hits"));
  json discrete = element;
  discrete["sampleTime"] = {1e-3, 0.0};
  json j = GprDiagram(discrete);
  j["connections"].push_back(Connect("dhat", "mean", "dhat", "d"));  // its own output as the target: no loop
  const Diagram diagram = BuildDiagram(j, dir_, "gpr_test.json");
  const auto& block = dynamic_cast<const Gpr&>(*diagram.blocks().at(2));
  ASSERT_EQ(block.input_ports().size(), 3u);
  EXPECT_EQ(block.input_ports()[2].name, "d");
  EXPECT_FALSE(block.input_ports()[2].direct_feedthrough);
  EXPECT_EQ(block.num_discrete_states(), model_->feature_count() * (model_->feature_count() + 1) + 1);
}

TEST_F(GprBlock, MissingOrCorruptModelFileNamesElementAndFile) {
  const json element = {{"name", "dhat"}, {"type", "gpr"}, {"parameters", {{"model", "broken.json"}}}};
  const std::string path = (dir_ / "broken.json").string();

  std::string e = BuildError(GprDiagram(element));
  EXPECT_THAT(e, HasSubstr("/elements/2: element 'dhat' (gpr): parameter model \"broken.json\" (" + path + ")"));
  EXPECT_THAT(e, HasSubstr("(" + path + "): no such file"));

  // Truncated: not JSON any more; the byte of the syntax error is given.
  fs::copy_file(dir_ / "model.json", dir_ / "broken.json");
  fs::resize_file(dir_ / "broken.json", fs::file_size(dir_ / "broken.json") / 3);
  e = BuildError(GprDiagram(element));
  EXPECT_THAT(e, HasSubstr("element 'dhat' (gpr): parameter model \"broken.json\""));
  EXPECT_THAT(e, HasSubstr(path + ": not a valid JSON file (corrupt or truncated?) at byte"));

  // Valid JSON, invalid model: every problem with its JSON pointer.
  json model = GprModelToJson(*model_);
  model["hyperparameters"]["noise_variance"] = -1.0;
  model.erase("weights");
  std::ofstream(dir_ / "broken.json", std::ios::trunc) << model.dump();
  e = BuildError(GprDiagram(element));
  EXPECT_THAT(e, HasSubstr("element 'dhat' (gpr): parameter model \"broken.json\""));
  EXPECT_THAT(e, HasSubstr("/hyperparameters/noise_variance"));
  EXPECT_THAT(e, HasSubstr("/weights"));

  // An empty parameter says what to give.
  e = BuildError(GprDiagram({{"name", "dhat"}, {"type", "gpr"}, {"parameters", {{"model", ""}}}}));
  EXPECT_THAT(e, HasSubstr("element 'dhat' (gpr): parameter model is empty"));
}

}  // namespace
}  // namespace mb
