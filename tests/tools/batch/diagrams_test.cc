// Every shipped diagram loads and validates, every shipped diagram, subsystem and sweep file validates against
// the generated schemas as written, and the committed sweep schema is the generated one.

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "engine/diagram_schema.h"
#include "tools/batch/sweep.h"
#include "tools/batch/sweep_schema.h"

namespace mb {
namespace {

namespace fs = std::filesystem;

TEST(ShippedDiagramsTest, EveryDiagramLoads) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(MB_SOURCE_DIR) / "diagrams")) {
    if (entry.path().extension() != ".json") continue;
    if (entry.path().filename().string().find("schema.json") != std::string::npos) continue;
    if (entry.path().parent_path().filename() == "subsystems") continue;  // parts of other diagrams
    if (entry.path().parent_path().filename() == "sweeps") continue;  // sweep files (sweep_test.cc loads them)
    if (entry.path().parent_path().filename() == "models") continue;  // GPR model files the diagrams load
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW({
      try {
        LoadDiagram(entry.path());
      } catch (const std::exception& e) {
        ADD_FAILURE() << e.what();
        throw;
      }
    });
    ++count;
  }
  EXPECT_GE(count, 2);
}

TEST(ShippedDiagramsTest, SchemaIsValidJsonWithLoaderKeys) {
  std::ifstream in(fs::path(MB_SOURCE_DIR) / "diagrams" / "schema.json");
  const auto schema = nlohmann::json::parse(in);
  for (const char* key : {"schemaVersion", "elements", "connectors", "connections", "defaultExperiment", "solver",
                          "log", "metrics", "free"}) {
    EXPECT_TRUE(schema["properties"].contains(key)) << key;
  }
  EXPECT_EQ(schema["properties"]["schemaVersion"]["const"], kDiagramSchemaVersion);
}

TEST(ShippedDiagramsTest, EveryDiagramSubsystemAndSweepValidatesAsWritten) {
  int diagrams = 0, sweeps = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(MB_SOURCE_DIR) / "diagrams")) {
    const std::string folder = entry.path().parent_path().filename().string();
    if (entry.path().extension() != ".json" || folder == "models") continue;
    if (entry.path().filename().string().find("schema.json") != std::string::npos) continue;
    SCOPED_TRACE(entry.path().string());
    if (folder == "sweeps") {
      EXPECT_NO_THROW(ReadSweepFile(entry.path()));
      std::ifstream in(entry.path());
      for (const auto& p : SweepSchemaProblems(nlohmann::json::parse(in))) ADD_FAILURE() << p.Text();
      ++sweeps;
    } else {
      for (const auto& p : DiagramSchemaProblems(ReadDiagramJson(entry.path()))) ADD_FAILURE() << p.Text();
      ++diagrams;
    }
  }
  EXPECT_GE(diagrams, 10);
  EXPECT_GE(sweeps, 5);
}

TEST(ShippedDiagramsTest, CommittedSweepSchemaIsTheGeneratedOne) {
  std::ifstream in(fs::path(MB_SOURCE_DIR) / "diagrams" / "sweep.schema.json");
  ASSERT_TRUE(in) << "diagrams/sweep.schema.json is missing";
  EXPECT_EQ(nlohmann::json::parse(in), SweepSchema())
      << "diagrams/sweep.schema.json has drifted: regenerate it with `motionblocks schema --sweep`";
}

}  // namespace
}  // namespace mb
