// `motionblocks schema` and the validation it stands for, as users meet it: a misspelled key in a diagram or a
// sweep file, or a --map on a connector the diagram lacks, is one clear message and a non-zero exit code.

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;
using testing::ProcessTempDir;
using testing::RunMotionblocks;

const std::string kSource = MB_SOURCE_DIR;

json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

fs::path WriteJson(const fs::path& path, const json& j) {
  std::ofstream(path) << j.dump(2);
  return path;
}

TEST(SchemaCommand, PrintsTheCommittedSchemas) {
  auto r = RunMotionblocks("schema");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(json::parse(r.output), ReadJson(kSource + "/diagrams/schema.json"))
      << "regenerate diagrams/schema.json with `motionblocks schema > diagrams/schema.json`";
  r = RunMotionblocks("schema --sweep");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(json::parse(r.output), ReadJson(kSource + "/diagrams/sweep.schema.json"))
      << "regenerate diagrams/sweep.schema.json with `motionblocks schema --sweep > diagrams/sweep.schema.json`";
}

TEST(SchemaCommand, RunRefusesAMisspelledStopTime) {
  const fs::path out = ProcessTempDir("mb_schema_run");
  json j = ReadJson(kSource + "/diagrams/emps/closed_loop.json");
  j["defaultExperiment"].erase("stopTime");
  j["defaultExperiment"]["stopTme"] = 0.01;
  const auto r = RunMotionblocks("run " + WriteJson(out / "d.json", j).string() + " --out " + (out / "o").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("/defaultExperiment/stopTme: unknown key 'stopTme' (did you mean 'stopTime'?)"));
  EXPECT_FALSE(fs::exists(out / "o" / "summary.json"));
  fs::remove_all(out);
}

TEST(SchemaCommand, SweepRefusesMisspelledKeys) {
  const fs::path out = ProcessTempDir("mb_schema_sweep");
  const std::string diagram = kSource + "/diagrams/paper/conventional.json";
  auto sweep = WriteJson(out / "s.json", {{"random", {{"seed", 1}, {"sampels", 3}, {"samples", 2},
                                                      {"parameters", {{"pd_p.gain", {{"uniform", {1, 2}}}}}}}}});
  auto r = RunMotionblocks("sweep " + diagram + " " + sweep.string() + " --out " + (out / "o").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("/random/sampels: unknown key 'sampels' (did you mean 'samples'?)"));
  sweep = WriteJson(out / "s2.json", {{"list", {{{"defaultExperiment.stopTme", 0.01}}}}});
  r = RunMotionblocks("sweep " + diagram + " " + sweep.string() + " --out " + (out / "o").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("/defaultExperiment/stopTme: unknown key 'stopTme' (did you mean 'stopTime'?)"));
  EXPECT_FALSE(fs::exists(out / "o" / "runs.csv"));
  fs::remove_all(out);
}

TEST(SchemaCommand, CompareRefusesAMapOnAnUnknownConnector) {
  const fs::path out = ProcessTempDir("mb_schema_map");
  const auto r = RunMotionblocks("compare " + kSource + "/diagrams/emps/rigid_body.json --measurement " + kSource +
                                 "/diagrams/emps/data/DATA_EMPS.csv --map forse=force_N --no-fit --out " +
                                 (out / "o").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("--map forse=force_N: the diagram has no connector 'forse' (did you mean "
                                  "'force'?); its input and output connectors: position, velocity, acceleration, "
                                  "pulse_force, force"));
  fs::remove_all(out);
}

// --map force=position_m compares newtons with metres: the units in the column names say so.
TEST(SchemaCommand, CompareRefusesAMapOfAnotherQuantity) {
  const fs::path out = ProcessTempDir("mb_schema_map_unit");
  const auto r = RunMotionblocks("compare " + kSource + "/diagrams/emps/rigid_body.json --measurement " + kSource +
                                 "/diagrams/emps/data/DATA_EMPS.csv --map force=position_m --no-fit --out " +
                                 (out / "o").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("--map force=position_m: the connector 'force' is in N but the column "
                                  "'position_m' is in m (its name's suffix): they measure different things"));
  fs::remove_all(out);
}

}  // namespace
}  // namespace mb
