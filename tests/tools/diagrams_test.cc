// Every shipped diagram loads and validates (the loader is the authority; diagrams/schema.json is for editors),
// and the schema itself is valid JSON naming the same top-level keys the loader accepts.

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"

namespace mb {
namespace {

namespace fs = std::filesystem;

TEST(ShippedDiagramsTest, EveryDiagramLoads) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(MB_SOURCE_DIR) / "diagrams")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "schema.json") continue;
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

}  // namespace
}  // namespace mb
