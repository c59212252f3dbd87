// Model file: round trip and the errors a corrupt or foreign file gives.
#include "models/gpr/gpr_io.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "models/gpr/gpr_fit.h"
#include "tests/gpr/synthetic_data.h"

namespace mb {
namespace {

namespace fs = std::filesystem;

class GprModelFile : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto data = testing::ConstantVelocityScans(0.1, 0.325, 15, 0.02, 21);
    GprFitOptions options;
    options.restarts = 0;
    options.source = "synthetic scans";
    model_ = new GprModel(FitGpr(data.x, data.xdot, data.d, options));
    options.kernel = GprKernel::kSeSe;
    ds_model_ = new GprModel(FitGpr(data.x, data.xdot, data.d, options));
  }
  static void TearDownTestSuite() {
    delete model_;
    delete ds_model_;
  }
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_gpr_io_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string LoadError(const nlohmann::json& j) {
    const fs::path path = dir_ / "model.json";
    std::ofstream(path) << j.dump();
    try {
      LoadGprModel(path);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no exception";
  }

  static GprModel* model_;
  static GprModel* ds_model_;
  fs::path dir_;
};
GprModel* GprModelFile::model_ = nullptr;
GprModel* GprModelFile::ds_model_ = nullptr;

TEST_F(GprModelFile, RoundTripPreservesEverything) {
  for (const GprModel* original : {model_, ds_model_}) {
    const fs::path path = dir_ / "model.json";
    SaveGprModel(*original, path);
    const GprModel loaded = LoadGprModel(path);
    EXPECT_EQ(loaded.kernel(), original->kernel());
    EXPECT_EQ(loaded.feature_count(), original->feature_count());
    EXPECT_EQ((loaded.data().weights - original->data().weights).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ((loaded.data().weight_covariance - original->data().weight_covariance)
                  .cwiseAbs()
                  .maxCoeff(),
              0.0);
    EXPECT_EQ(loaded.data().provenance.source, "synthetic scans");
    EXPECT_EQ(loaded.data().provenance.priors[kLogLengthScaleXdot].median,
              original->data().provenance.priors[kLogLengthScaleXdot].median);
    for (double x : {-0.2, 0.15, 0.9}) {
      for (double v : {0.0, 0.2, 0.7}) {
        double m1 = 0, s1 = 0, m2 = 0, s2 = 0;
        original->Predict(x, v, &m1, &s1);
        loaded.Predict(x, v, &m2, &s2);
        EXPECT_EQ(m1, m2);
        EXPECT_EQ(s1, s2);
      }
    }
    EXPECT_FALSE(fs::exists(dir_ / "model.json.tmp"));
  }
}

TEST_F(GprModelFile, CorruptFileIsAClearError) {
  const fs::path path = dir_ / "model.json";
  SaveGprModel(*model_, path);
  fs::resize_file(path, fs::file_size(path) / 2);  // truncated
  try {
    LoadGprModel(path);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ": not a valid JSON file (corrupt or truncated?)"),
              std::string::npos)
        << e.what();
  }
  try {
    LoadGprModel(dir_ / "missing.json");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

TEST_F(GprModelFile, WrongVersionOrFormatIsRejected) {
  nlohmann::json j = GprModelToJson(*model_);
  j["version"] = 2;
  EXPECT_NE(LoadError(j).find("/version: file version 2 is not supported (this build reads version 1)"),
            std::string::npos)
      << LoadError(j);
  j = GprModelToJson(*model_);
  j["format"] = "something-else";
  EXPECT_NE(LoadError(j).find("/format: expected \"motionblocks-gpr-model\""), std::string::npos);
}

TEST_F(GprModelFile, EveryMissingOrInvalidFieldIsReportedWithItsPointer) {
  nlohmann::json j = GprModelToJson(*model_);
  j["hyperparameters"].erase("length_scale_xdot");
  j["hyperparameters"]["noise_variance"] = -1.0;
  j["weights"][3] = nullptr;  // how nlohmann writes a NaN
  j["trained_range"]["x"] = nlohmann::json::array({0.3, 0.1});
  const std::string error = LoadError(j);
  EXPECT_NE(error.find("/hyperparameters/length_scale_xdot: missing"), std::string::npos) << error;
  EXPECT_NE(error.find("/hyperparameters/noise_variance: must be > 0"), std::string::npos) << error;
  EXPECT_NE(error.find("/weights/3: must be a number, but is null (NaN and infinity are not valid here)"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("/trained_range/x: must be [min, max] with min <= max"), std::string::npos)
      << error;
  j = GprModelToJson(*model_);
  j["weights"].erase(0);
  EXPECT_NE(LoadError(j).find("/weights: must have " + std::to_string(model_->feature_count()) +
                              " entries"),
            std::string::npos);
  j = GprModelToJson(*model_);
  j["kernel"] = "SE";
  EXPECT_NE(LoadError(j).find("/kernel: must be \"PS\" or \"DS\", got \"SE\""), std::string::npos);
}

// Issue 30: a model that is no posterior is refused when loaded, not used (all weights 1e308 predicted NaN; a
// negative covariance gave std 0 everywhere).
TEST_F(GprModelFile, WeightsThatOverflowOrACovarianceNotPositiveSemidefiniteAreRefused) {
  nlohmann::json j = GprModelToJson(*model_);
  for (auto& w : j["weights"]) w = 1e308;
  const std::string overflow = LoadError(j);
  // inf or NaN, depending on the order in which the feature kernels add the overflowing products.
  EXPECT_TRUE(overflow.find(": invalid GPR model file:\n  /weights: the model predicts inf ± ") != std::string::npos ||
              overflow.find(": invalid GPR model file:\n  /weights: the model predicts NaN ± ") != std::string::npos)
      << overflow;
  EXPECT_NE(overflow.find("m/s inside its trained range (weights or mean too large for double arithmetic): the file "
                          "was edited or is corrupt; refit the model (motionblocks fit-gpr)"),
            std::string::npos)
      << overflow;
  j = GprModelToJson(*model_);
  for (auto& c : j["weight_covariance_lower"]) c = -std::abs(c.get<double>()) - 1e-3;
  const std::string negative = LoadError(j);
  EXPECT_NE(negative.find("/weight_covariance_lower: the weight covariance is not positive semidefinite (smallest "
                          "eigenvalue -"),
            std::string::npos)
      << negative;
  EXPECT_NE(negative.find("): the file was edited or is corrupt; refit the model (motionblocks fit-gpr)"),
            std::string::npos);
  j = GprModelToJson(*model_);
  j["mean"] = std::numeric_limits<double>::infinity();
  EXPECT_NE(LoadError(j).find("/mean: must be a number, but is null (NaN and infinity are not valid here)"),
            std::string::npos)
      << LoadError(j);  // nlohmann writes infinity as null
  EXPECT_NO_THROW(GprModelFromJson(GprModelToJson(*model_)));  // a fitted model passes
}

// Issue 41: a covariance of 1e200 everywhere (positive semidefinite, rank one) predicted ± 1e101 and was read; a
// posterior is never less certain than its prior.
TEST_F(GprModelFile, ACovarianceAboveThePriorIsRefused) {
  for (const GprModel* model : {model_, ds_model_}) {
    nlohmann::json j = GprModelToJson(*model);
    for (auto& c : j["weight_covariance_lower"]) c = 1e200;
    const std::string error = LoadError(j);
    EXPECT_NE(error.find(": invalid GPR model file:\n  /weight_covariance_lower: the model's standard deviation at "
                         "x = "),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("a posterior is never less certain than its prior, so the covariance was edited or is "
                         "corrupt; refit the model (motionblocks fit-gpr)"),
              std::string::npos)
        << error;
    EXPECT_NO_THROW(GprModelFromJson(GprModelToJson(*model)));  // the fitted model passes
  }
}

// Issue 41: keys the reader does not know are refused at every level, with the closest known key.
TEST_F(GprModelFile, UnknownKeysAreRefusedWithTheClosestKnownOne) {
  nlohmann::json j = GprModelToJson(*model_);
  j["extra"] = 1;
  j["hyperparameters"]["lenght_scale_x"] = 0.1;
  j["basis"]["x_domain"] = {{"center", 0.0}, {"half_width", 1.0}, {"count", 8}};  // a "DS" key in a "PS" model
  j["provenance"]["priors"]["period"]["medain"] = 1.0;
  const std::string error = LoadError(j);
  EXPECT_NE(error.find("\n  /extra: unknown key; the keys here are: format, version, kernel, hyperparameters, mean, "
                       "trained_range, basis, weights, weight_covariance_lower, provenance (a model file holds what "
                       "fit-gpr writes: refit the model, or remove the key)"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("\n  /hyperparameters/lenght_scale_x: unknown key (did you mean 'length_scale_x'?)"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("\n  /basis/x_domain: unknown key (did you mean 'xdot_domain'?); the keys here are: harmonics, "
                       "period, xdot_domain"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("\n  /provenance/priors/period/medain: unknown key (did you mean 'median'?)"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace mb
