// The HIL loop allocates nothing: the allocation count (tests/alloc_counter.h) is read at the first sample
// and at the safe stop of RunHilLoop, on the shipped HIL diagram with a gpr block added to the controller
// (its output is added to the PD force), against the in-process test board — with the model fixed and learning
// online (the same block as in simulation: blocks/gpr.h).
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "engine/file_access.h"
#include "hw/board_registry.h"
#include "hw/hil_runner.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_io.h"
#include "tests/alloc_counter.h"
#include "tests/gpr/synthetic_data.h"
#include "tests/hw/hil_test_util.h"
#include "tests/hw/test_board.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json Connect(const std::string& se, const std::string& sc, const std::string& ee, const std::string& ec) {
  return {{"startElement", se}, {"startConnector", sc}, {"endElement", ee}, {"endConnector", ec}};
}

void ExpectNoAllocationInTheLoop(bool learning_online) {
  SCOPED_TRACE(learning_online ? "learning online" : "model fixed");
  const fs::path dir = fs::temp_directory_path() / "mb_hil_alloc";
  fs::create_directories(dir);
  const auto data = testing::ConstantVelocityScans(0.1, 0.325, 15, 0.02, 51);
  GprFitOptions fit;
  fit.restarts = 0;
  SaveGprModel(FitGpr(data.x, data.xdot, data.d, fit), dir / "model.json");

  // u = PD + gpr(x, ẋ = 0.2 m/s) into the I/O subsystem.
  json j = testing::HilDiagramJson(0.3);
  j["elements"].push_back({{"name", "dhat"}, {"type", "gpr"}, {"sampleTime", {1e-3, 0.0}},
                           {"parameters", {{"model", (dir / "model.json").string()}, {"output_std", true}}}});
  j["elements"].push_back({{"name", "speed"}, {"type", "constant"}, {"parameters", {{"value", 0.2}}}});
  j["elements"].push_back({{"name", "total"}, {"type", "sum"}, {"parameters", {{"signs", "++"}}}});
  for (auto& c : j["connections"]) {
    if (c.value("startElement", "") == "controller" && c.value("endElement", "") == "plant") {
      c["endElement"] = "total";
      c["endConnector"] = "u1";
    }
  }
  j["connections"].push_back(Connect("plant", "x", "dhat", "x"));
  j["connections"].push_back(Connect("speed", "y", "dhat", "xdot"));
  j["connections"].push_back(Connect("dhat", "mean", "total", "u2"));
  j["connections"].push_back(Connect("total", "y", "plant", "f"));
  j["log"] = {"dhat.mean", "dhat.std", "total.y"};
  if (learning_online) {  // the target: the force the controller asks for (any signal will do here)
    j["elements"][j["elements"].size() - 3]["parameters"]["learning"] = "online";
    j["elements"][j["elements"].size() - 3]["parameters"]["forgetting"] = 0.999;
    j["connections"].push_back(Connect("total", "y", "dhat", "d"));
  }

  testing::TestBoard board;
  ScopedBoardAttachment attachment(board);
  AllowDiagramFilesUnder(std::string(MB_SOURCE_DIR) + "/diagrams/hil/subsystems");  // the shipped I/O subsystem
  const Diagram diagram = BuildDiagram(j, dir, "hil_alloc.json");
  long at_first_sample = -1, at_safe_stop = -1;
  board.on_first_sample = [&] { at_first_sample = ::mb::testing::AllocationCount(); };
  board.on_safe_stop = [&] { at_safe_stop = ::mb::testing::AllocationCount(); };
  const HilResult r = RunHilLoop(diagram, board, HilOptions{});
  fs::remove_all(dir);

  ASSERT_TRUE(r.completed) << r.stop_reason;
  EXPECT_EQ(r.statistics.ticks, 300);
  ASSERT_GE(at_first_sample, 0) << "the board never saw a first sample";
  ASSERT_GE(at_safe_stop, 0) << "the board never saw the safe stop";
  EXPECT_EQ(at_safe_stop - at_first_sample, 0) << "allocations inside the real-time loop";
  // The gpr block really ran: a finite, non-zero disturbance estimate in the log.
  const auto& mean = r.log.Column("dhat.mean");
  ASSERT_EQ(mean.size(), 301u);
  EXPECT_TRUE(std::isfinite(mean.back()));
  EXPECT_GT(std::abs(mean.back()), 0.0);
  // The counter does count: one allocation is seen.
  const long before_probe = ::mb::testing::AllocationCount();
  void* p = ::operator new(16);
  const long after_probe = ::mb::testing::AllocationCount();
  ::operator delete(p);
  EXPECT_EQ(after_probe - before_probe, 1);
}

TEST(HilAllocationTest, TheLoopAllocatesNothingWithAGprBlockInTheController) {
  ExpectNoAllocationInTheLoop(false);
  ExpectNoAllocationInTheLoop(true);
}

}  // namespace
}  // namespace mb
