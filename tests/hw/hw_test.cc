// Unit tests of the HIL path that need no second process: the wire format, swapping the plant subsystem, the
// HIL blocks' errors and scaling, and the runner's safe stop on missed samples and overruns (with an in-process
// test board).

#include <algorithm>
#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"
#include "hw/board_registry.h"
#include "hw/hil_diagram.h"
#include "hw/hil_runner.h"
#include "hw/quanser_board.h"
#include "hw/udp_protocol.h"
#include "tests/hw/hil_test_util.h"
#include "tests/hw/test_board.h"

namespace mb {
namespace {

using ::testing::HasSubstr;
using testing::HilDiagramJson;
using testing::TestBoard;

TEST(UdpProtocolTest, RoundTripKeepsEveryField) {
  BoardPacket p;
  p.type = PacketType::kOutputs;
  p.sequence = 0xFFFFFFFEu;
  p.timestamp_ns = -1234567890123LL;
  p.digital = 0xA5A5A5A5u;
  for (std::size_t i = 0; i < p.encoder_counts.size(); ++i) p.encoder_counts[i] = -2147483647 + static_cast<int>(i);
  for (std::size_t i = 0; i < p.analog_volts.size(); ++i) p.analog_volts[i] = -9.75 + 0.125 * static_cast<double>(i);
  PacketBytes bytes;
  EncodePacket(p, &bytes);
  // Little-endian magic on the wire.
  EXPECT_EQ(static_cast<int>(bytes[0]), 0x56);
  EXPECT_EQ(static_cast<int>(bytes[3]), 0x4D);
  BoardPacket q;
  ASSERT_TRUE(DecodePacket(bytes.data(), bytes.size(), &q));
  EXPECT_EQ(q.type, p.type);
  EXPECT_EQ(q.sequence, p.sequence);
  EXPECT_EQ(q.timestamp_ns, p.timestamp_ns);
  EXPECT_EQ(q.digital, p.digital);
  EXPECT_EQ(q.encoder_counts, p.encoder_counts);
  EXPECT_EQ(q.analog_volts, p.analog_volts);
}

TEST(UdpProtocolTest, RejectsWrongSizeMagicVersionAndType) {
  BoardPacket p;
  PacketBytes bytes;
  EncodePacket(p, &bytes);
  BoardPacket q;
  EXPECT_FALSE(DecodePacket(bytes.data(), bytes.size() - 1, &q));
  PacketBytes bad = bytes;
  bad[0] = std::byte{0};
  EXPECT_FALSE(DecodePacket(bad.data(), bad.size(), &q));
  bad = bytes;
  bad[4] = std::byte{2};  // version 2
  EXPECT_FALSE(DecodePacket(bad.data(), bad.size(), &q));
  bad = bytes;
  bad[6] = std::byte{9};  // type 9
  EXPECT_FALSE(DecodePacket(bad.data(), bad.size(), &q));
}

TEST(HilDiagramTest, ReplacesTheSubsystemAndDropsItsOverrides) {
  nlohmann::json j = {{"elements",
                       {{{"name", "plant"}, {"type", "subsystem"}, {"diagram", "plant.json"},
                         {"parameters", {{"body.mass", 2.0}}}},
                        {{"name", "k"}, {"type", "gain"}}}},
                      {"log", {"plant/body.v", "k.y"}}};
  std::vector<std::string> dropped;
  const auto out = ReplaceSubsystem(j, SubsystemReplacement::Parse("plant=/tmp/io.json"), "d.json", &dropped);
  EXPECT_EQ(out["elements"][0]["diagram"], "/tmp/io.json");
  EXPECT_FALSE(out["elements"][0].contains("parameters"));
  EXPECT_EQ(out["log"], nlohmann::json({"k.y"}));
  EXPECT_THAT(dropped, ::testing::ElementsAre(HasSubstr("plant.body.mass = 2.0"), HasSubstr("plant/body.v")));
}

TEST(HilDiagramTest, ErrorsNameTheElementAndTheFix) {
  nlohmann::json j = {{"elements", {{{"name", "plant"}, {"type", "rigid_body"}}}}};
  std::vector<std::string> dropped;
  try {
    ReplaceSubsystem(j, {"plant", "/tmp/io.json"}, "d.json", &dropped);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("element 'plant' is a 'rigid_body', not a subsystem"));
  }
  try {
    ReplaceSubsystem(j, {"stage", "/tmp/io.json"}, "d.json", &dropped);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("no element named 'stage'; the diagram has: plant"));
  }
  EXPECT_THROW(SubsystemReplacement::Parse("plant"), std::invalid_argument);
}

TEST(HilBlocksTest, WithoutABoardTheDiagramDoesNotBuild) {
  BoardRegistry::Global().Detach();
  try {
    BuildDiagram(HilDiagramJson(1.0), testing::HilDiagramDir(), "hil.json");
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("no I/O board is attached"));
  }
}

TEST(HilBlocksTest, ScaleAndClampThroughTheBoardImage) {
  TestBoard board;
  ScopedBoardAttachment attachment(board);
  nlohmann::json j = HilDiagramJson(0.01);
  j["elements"][2]["parameters"]["kp"] = 1e9;  // r(1 ms) = 0.39 µm → f ≈ 390 N: far beyond the 10 V clamp
  const Diagram diagram = BuildDiagram(j, testing::HilDiagramDir(), "hil.json");
  Simulator sim(diagram);
  sim.Initialize();
  // At t = 0: r = 0, x = 0 → zero force, zero volts.
  EXPECT_EQ(board.analog_output(0), 0.0);
  SampleTiming timing;
  board.Start(1e-3);
  board.WaitForSample(&timing);  // plant at rest: counts stay 0
  sim.AdvanceTo(1e-3);
  EXPECT_NEAR(sim.SignalValue(diagram.ResolveSignal("position")), 0.0, 1e-12);
  const double force = sim.SignalValue(diagram.ResolveSignal("force"));
  EXPECT_GT(force, 300.0);
  EXPECT_EQ(board.analog_output(0), 10.0);  // 1 N/V, clamped to the 10 V limit
  EXPECT_EQ(sim.SignalValue(diagram.ResolveSignal("plant/amplifier.voltage")), 10.0);

  // A channel the board does not have (the I/O subsystem inline, encoder on channel 5).
  nlohmann::json wrong = HilDiagramJson(0.01);
  nlohmann::json io = ReadDiagramJson(testing::HilDiagramDir() / "subsystems" / "hil_io.json");
  io["elements"][0]["parameters"]["channel"] = 5;
  wrong["elements"][3]["diagram"] = io;
  try {
    BuildDiagram(wrong, testing::HilDiagramDir(), "hil.json");
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("channel 5 does not exist on test board (it has 2 encoder channels, 0–1)"));
  }
}

TEST(HilRunnerTest, RunsEveryTickAndTracks) {
  TestBoard board;
  ScopedBoardAttachment attachment(board);
  const Diagram diagram = BuildDiagram(HilDiagramJson(0.5), testing::HilDiagramDir(), "hil.json");
  const HilResult r = RunHilLoop(diagram, board, HilOptions{});
  EXPECT_TRUE(r.completed) << r.stop_reason;
  EXPECT_EQ(r.statistics.ticks, 500);
  EXPECT_EQ(board.samples(), 500);
  EXPECT_EQ(board.writes(), 501);  // the t0 outputs, then one write per tick
  EXPECT_EQ(board.safe_stops(), 1);
  EXPECT_EQ(board.analog_output(0), 0.0);
  EXPECT_EQ(r.log.time.size(), 501u);
  EXPECT_NEAR(r.log.time.back(), 0.5, 1e-12);
  // The unit-mass test plant follows the 5 mm reference to within a millimetre.
  EXPECT_LT(r.metrics.at("tracking_max"), 1e-3);
  EXPECT_NEAR(r.period, 1e-3, 1e-15);
}

TEST(HilRunnerTest, MissedSampleStreakTriggersTheSafeStop) {
  TestBoard board(TestBoard::Fault::kMissAfter, 100);
  ScopedBoardAttachment attachment(board);
  const Diagram diagram = BuildDiagram(HilDiagramJson(1.0), testing::HilDiagramDir(), "hil.json");
  HilOptions options;
  options.max_missed_streak = 20;
  const HilResult r = RunHilLoop(diagram, board, options);
  EXPECT_FALSE(r.completed);
  EXPECT_THAT(r.stop_reason, HasSubstr("watchdog"));
  EXPECT_THAT(r.stop_reason, HasSubstr("tick 120"));
  EXPECT_EQ(r.statistics.ticks, 120);
  EXPECT_EQ(r.statistics.missed_samples, 20);
  EXPECT_EQ(board.safe_stops(), 1);
  EXPECT_EQ(board.analog_output(0), 0.0);
  EXPECT_EQ(r.log.time.size(), 121u);
  EXPECT_THAT(r.metrics_error, ::testing::IsEmpty());  // metrics over the whole window still compute
}

TEST(HilRunnerTest, OverrunStreakTriggersTheSafeStop) {
  TestBoard board(TestBoard::Fault::kOverrunAfter, 50);
  ScopedBoardAttachment attachment(board);
  const Diagram diagram = BuildDiagram(HilDiagramJson(1.0), testing::HilDiagramDir(), "hil.json");
  HilOptions options;
  options.max_overrun_streak = 5;
  const HilResult r = RunHilLoop(diagram, board, options);
  EXPECT_FALSE(r.completed);
  EXPECT_THAT(r.stop_reason, HasSubstr("overrun streak"));
  EXPECT_EQ(r.statistics.ticks, 55);
  // The five forced overruns end the run. The test board's other ticks are scheduled at their wake time on the
  // machine's own clock, so a tick the OS preempted for over a period (a loaded CI machine) counts as well: the
  // streak, not the total, is deterministic.
  EXPECT_GE(r.statistics.overruns, 5);
  EXPECT_LE(r.statistics.overruns, 50);
  EXPECT_EQ(r.statistics.max_overrun_streak, 5);
  EXPECT_EQ(board.safe_stops(), 1);
}

TEST(HilRunnerTest, StopRequestTriggersTheSafeStop) {
  TestBoard board;
  ScopedBoardAttachment attachment(board);
  const Diagram diagram = BuildDiagram(HilDiagramJson(1.0), testing::HilDiagramDir(), "hil.json");
  std::atomic<bool> stop{false};
  board.on_first_sample = [&] { stop.store(true); };
  HilOptions options;
  options.stop_request = &stop;
  const HilResult r = RunHilLoop(diagram, board, options);
  EXPECT_FALSE(r.completed);
  EXPECT_THAT(r.stop_reason, HasSubstr("stop requested"));
  EXPECT_EQ(r.statistics.ticks, 1);
}

TEST(HilRunnerTest, RejectsContinuousStatesOutsideThePlant) {
  TestBoard board;
  ScopedBoardAttachment attachment(board);
  // The unreplaced diagram still has the rigid body.
  const auto path = testing::HilDiagramDir() / "pd_rigid_body.json";
  const Diagram diagram = LoadDiagram(path);
  try {
    RunHilLoop(diagram, board, HilOptions{});
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("block 'plant/body' has 2 continuous state(s)"));
  }
  EXPECT_FALSE(board.started());
}

TEST(QuanserBoardTest, AvailabilityMatchesTheBuild) {
  if (QuanserBackendAvailable()) GTEST_SKIP() << "built with the Quanser SDK: opening needs a board";
  try {
    OpenQuanserBoard(QuanserBoardOptions{});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("-DWITH_QUANSER=ON"));
  }
}

}  // namespace
}  // namespace mb
