// tools/batch/sweep_mpi.h under `mpirun --oversubscribe -n 3` (registered by tests/tools/CMakeLists.txt): rank 0
// hands the runs to ranks 1 and 2 and writes runs.csv; its rows equal those of the single-process sweep (RunSweep),
// a failed run included. Every rank runs this test; ranks > 0 only simulate.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/batch/sweep_test_files.h"
#include "tools/batch/sweep.h"
#include "tools/batch/sweep_mpi.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

TEST(SweepMpiTest, RowsEqualTheSingleProcessSweep) {
  const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
  ASSERT_NE(rank, nullptr) << "run under mpirun -n 3";
  const fs::path dir = MB_MPI_TEST_DIR;  // the same folder on every rank
  const fs::path diagram = dir / "gain.json";
  if (std::string(rank) == "0") {  // the others read the files only after rank 0 has started the sweep
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(diagram) << testing::GainDiagram().dump(2);
  }
  const SweepSpec spec = ParseSweep(json::parse(R"({"set": {"c.value": 3.0},
      "grid": {"k.gain": [1, 2, 3, 4, 5, 6, 7], "defaultExperiment.stopTime": [0.01, 0.02, -1]}})"), "s.json");
  SweepOptions options;
  options.progress = false;
  const auto outcome = RunSweepMpi(diagram, spec, dir / "mpi", options);
  if (std::string(rank) != "0") {
    EXPECT_FALSE(outcome.has_value());
    return;
  }
  ASSERT_TRUE(outcome.has_value());
  EXPECT_EQ(outcome->ran, 21);
  EXPECT_EQ(outcome->failed, 7);  // stopTime -1
  EXPECT_DOUBLE_EQ(outcome->rows[13].metrics.at("y_final"), 21.0);  // stopTime 0.02 (keys sorted), k.gain 7
  RunSweep(diagram, spec, dir / "single", options);
  EXPECT_EQ(testing::RunsWithoutWallTime(dir / "mpi" / "runs.csv"),
            testing::RunsWithoutWallTime(dir / "single" / "runs.csv"));
  std::ifstream in(dir / "mpi" / "runs.json");
  EXPECT_EQ(json::parse(in)["runs"].size(), 21u);
}

}  // namespace
}  // namespace mb
