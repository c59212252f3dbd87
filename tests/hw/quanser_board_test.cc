// The Quanser backend (hw/quanser_board.cc), compiled with MB_WITH_QUANSER against the test double of the HIL C API
// (tests/hw/fake_hil/) and run by the real HIL runner on the shipped HIL diagram: the call order of DESIGN.md, the
// safe stop with zero volts on every fault, no allocation in the loop, and the tracking of the simulated run within
// the tolerance the UDP virtual stage is held to (virtual_stage_test.cc).
//
// The double's clock is simulated (fake_hil.h): each hil_task_read_encoder advances the plant by one period and
// returns at once, so no result here depends on the machine keeping 1 kHz; the runner's overrun guard, which reads
// the wall clock, is relaxed for that reason (as in virtual_stage_test.cc), and no test needs to skip itself.

#include "hw/quanser_board.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"
#include "hw/board_registry.h"
#include "hw/hil_runner.h"
#include "tests/alloc_counter.h"
#include "tests/hw/fake_hil/fake_hil.h"
#include "tests/hw/hil_test_util.h"

namespace mb {
namespace {

using fake_hil::Call;
using fake_hil::Fault;
using ::testing::ElementsAreArray;
using ::testing::HasSubstr;

HilOptions Relaxed() {
  HilOptions options;
  options.max_overrun_streak = 1 << 30;  // the double's clock is simulated: the wall clock says nothing here
  return options;
}

// The HIL loop on the shipped diagram (plant swapped for board I/O) against a Quanser board on the double.
HilResult RunOnQuanser(double stop_time) {
  const std::unique_ptr<IoBoard> board = OpenQuanserBoard(QuanserBoardOptions{});
  ScopedBoardAttachment attachment(*board);
  const Diagram diagram = BuildDiagram(testing::HilDiagramJson(stop_time), testing::HilDiagramDir(), "hil.json");
  return RunHilLoop(diagram, *board, Relaxed());
}

std::vector<Call> StartCalls() {
  return {
      Call::kOpen,          Call::kSetEncoderCounts,        Call::kWriteAnalog, Call::kWatchdogSetAnalogExpirationState,
      Call::kWatchdogStart, Call::kTaskCreateEncoderReader, Call::kTaskStart};
}

// SafeStop (from the runner, then again from the board's destructor, which closes).
std::vector<Call> StopCalls() {
  return {Call::kWriteAnalog,   Call::kTaskStop,    Call::kTaskDelete, Call::kWatchdogStop,
          Call::kWatchdogClear, Call::kWriteAnalog, Call::kClose};
}

// The volts of every hil_write_analog from the first one after `from` (index into the record) on.
std::vector<double> VoltsWrittenFrom(std::size_t from) {
  std::vector<double> volts;
  const auto record = fake_hil::Record();
  for (std::size_t i = from; i < record.size(); ++i) {
    if (record[i].call == Call::kWriteAnalog) volts.push_back(record[i].volts);
  }
  return volts;
}

std::size_t IndexOf(const std::vector<Call>& calls, Call call) {
  return static_cast<std::size_t>(std::find(calls.begin(), calls.end(), call) - calls.begin());
}

TEST(QuanserBoardTest, TheBackendIsBuiltHere) { EXPECT_TRUE(QuanserBackendAvailable()); }

TEST(QuanserBoardTest, CallsTheHilApiInTheOrderOfTheDesign) {
  fake_hil::Reset();
  const HilResult r = RunOnQuanser(0.05);
  ASSERT_TRUE(r.completed) << r.stop_reason;
  ASSERT_EQ(r.statistics.ticks, 50);
  // open → encoder counts, the watchdog's expiration state → task → loop → stop, delete, watchdog stop, close.
  std::vector<Call> expected = StartCalls();
  expected.insert(expected.end(), {Call::kWriteAnalog, Call::kWatchdogReload});  // the outputs at t0
  for (int k = 0; k < 50; ++k) {
    expected.insert(expected.end(), {Call::kTaskReadEncoder, Call::kWriteAnalog, Call::kWatchdogReload});
  }
  const std::vector<Call> stop = StopCalls();
  expected.insert(expected.end(), stop.begin(), stop.end());
  EXPECT_THAT(fake_hil::Calls(), ElementsAreArray(expected));
  for (const auto& c : fake_hil::Record()) EXPECT_GE(c.result, 0) << fake_hil::ToString(c.call);
  EXPECT_EQ(fake_hil::Unrecorded(), 0);
  EXPECT_DOUBLE_EQ(fake_hil::TaskFrequency(), 1000.0);  // hil_task_start at 1/period
  EXPECT_DOUBLE_EQ(fake_hil::WatchdogTimeout(), 0.01);  // QuanserBoardOptions' 10 ms
  EXPECT_EQ(fake_hil::SamplesRead(), 50);
  EXPECT_FALSE(fake_hil::IsOpen());
  EXPECT_EQ(fake_hil::AppliedVolts(), 0.0);
  EXPECT_NE(VoltsWrittenFrom(0)[5], 0.0);  // the controller did drive the plant
  EXPECT_GT(fake_hil::Position(), 0.0);
}

// What every fault must end with: the outputs written to 0 V after the fault, the task stopped and deleted, the
// watchdog stopped, the board closed, and the amplifier at 0 V.
void ExpectSafeStop(std::size_t fault_index) {
  const std::vector<Call> calls = fake_hil::Calls();
  const std::vector<double> volts = VoltsWrittenFrom(fault_index);
  ASSERT_FALSE(volts.empty()) << "no output written after the fault";
  for (double v : volts) EXPECT_EQ(v, 0.0);
  const std::vector<Call> tail(calls.begin() + static_cast<std::ptrdiff_t>(fault_index) + 1, calls.end());
  EXPECT_LT(IndexOf(tail, Call::kWriteAnalog), IndexOf(tail, Call::kWatchdogStop));
  EXPECT_LT(IndexOf(tail, Call::kWatchdogStop), IndexOf(tail, Call::kClose));
  EXPECT_EQ(calls.back(), Call::kClose);
  EXPECT_FALSE(fake_hil::IsOpen());
  EXPECT_EQ(fake_hil::AppliedVolts(), 0.0);
}

std::size_t LastFailedCall() {
  const auto record = fake_hil::Record();
  for (std::size_t i = record.size(); i-- > 0;) {
    if (record[i].result < 0) return i;
  }
  return record.size();
}

TEST(QuanserBoardTest, AReadTimeoutStopsSafelyAtZeroVolts) {
  fake_hil::Reset({}, Fault::kReadTimeout, 100);
  const HilResult r = RunOnQuanser(1.0);
  EXPECT_FALSE(r.completed);
  EXPECT_THAT(r.stop_reason, HasSubstr("board fault while reading the inputs (safe stop at t = 0.0990 s, tick 99"));
  const std::size_t fault = LastFailedCall();
  ASSERT_LT(fault, fake_hil::Record().size());
  EXPECT_EQ(fake_hil::Record()[fault].call, Call::kTaskReadEncoder);
  ExpectSafeStop(fault);
  const std::vector<Call> calls = fake_hil::Calls();
  ASSERT_GE(calls.size(), 7u);
  EXPECT_THAT(std::vector<Call>(calls.end() - 7, calls.end()), ElementsAreArray(StopCalls()));
}

TEST(QuanserBoardTest, AnExpiredWatchdogStopsSafelyAtZeroVolts) {
  fake_hil::Reset({}, Fault::kWatchdogExpired, 200);
  const HilResult r = RunOnQuanser(1.0);
  EXPECT_FALSE(r.completed);
  EXPECT_THAT(r.stop_reason, HasSubstr("board fault while writing the outputs (safe stop at t = 0.2000 s, tick 200"));
  // hil_watchdog_reload said 0 (expired): the outputs held their expiration state, 0 V, from then on.
  const auto record = fake_hil::Record();
  std::size_t expired = record.size();
  for (std::size_t i = 0; i < record.size(); ++i) {
    if (record[i].call == Call::kWatchdogReload && record[i].result == 0) {
      expired = i;
      break;
    }
  }
  ASSERT_LT(expired, record.size());
  ExpectSafeStop(expired);
  const std::vector<Call> calls = fake_hil::Calls();
  ASSERT_GE(calls.size(), 7u);
  EXPECT_THAT(std::vector<Call>(calls.end() - 7, calls.end()), ElementsAreArray(StopCalls()));
}

TEST(QuanserBoardTest, AFailedOpenSaysWhatToCheckAndCallsNothingElse) {
  fake_hil::Reset({}, Fault::kOpenFails);
  try {
    OpenQuanserBoard(QuanserBoardOptions{});
    FAIL() << "expected hil_open to fail";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(),
                 "hil_open(q8_usb, 0): fake HIL: injected fault (Quanser error 1073); check the cable, the "
                 "driver and the board type (--quanser-board)");
  }
  EXPECT_THAT(fake_hil::Calls(), ElementsAreArray({Call::kOpen}));
}

TEST(QuanserBoardTest, AFailedTaskStartStopsSafelyAndNamesTheCall) {
  fake_hil::Reset({}, Fault::kTaskStartFails);
  {
    const std::unique_ptr<IoBoard> board = OpenQuanserBoard(QuanserBoardOptions{});
    ScopedBoardAttachment attachment(*board);
    const Diagram diagram = BuildDiagram(testing::HilDiagramJson(0.1), testing::HilDiagramDir(), "hil.json");
    try {
      RunHilLoop(diagram, *board, Relaxed());
      FAIL() << "expected hil_task_start to fail";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "hil_task_start on quanser q8_usb 0: fake HIL: injected fault (Quanser error 1073)");
    }
  }
  const std::size_t fault = LastFailedCall();
  EXPECT_EQ(fake_hil::Record()[fault].call, Call::kTaskStart);
  ExpectSafeStop(fault);
  const std::vector<Call> calls = fake_hil::Calls();
  EXPECT_THAT(std::vector<Call>(calls.begin() + static_cast<std::ptrdiff_t>(fault) + 1, calls.end()),
              ElementsAreArray({Call::kWriteAnalog, Call::kTaskDelete, Call::kWatchdogStop, Call::kWatchdogClear,
                                Call::kWriteAnalog, Call::kClose}));
}

long g_at_first_read = -1;
long g_at_task_stop = -1;

TEST(QuanserBoardTest, TheLoopAllocatesNothing) {
  fake_hil::Reset();
  g_at_first_read = g_at_task_stop = -1;
  fake_hil::SetLoopHooks([] { g_at_first_read = ::mb::testing::AllocationCount(); },
                         [] { g_at_task_stop = ::mb::testing::AllocationCount(); });
  const HilResult r = RunOnQuanser(0.3);
  fake_hil::SetLoopHooks(nullptr, nullptr);
  ASSERT_TRUE(r.completed) << r.stop_reason;
  EXPECT_EQ(r.statistics.ticks, 300);
  ASSERT_GE(g_at_first_read, 0);
  ASSERT_GE(g_at_task_stop, 0);
  EXPECT_EQ(g_at_task_stop - g_at_first_read, 0) << "allocations inside the real-time loop";
}

TEST(QuanserBoardTest, TracksAsTheSimulatedRunWithinTheVirtualStagesTolerance) {
  const Diagram simulated = LoadDiagram(testing::HilDiagramDir() / "pd_rigid_body.json");
  Simulator sim(simulated);
  const SimulationResult expected = sim.Run();
  fake_hil::Reset();
  const HilResult r = RunOnQuanser(simulated.experiment().stop_time);
  ASSERT_TRUE(r.completed) << r.stop_reason;
  ASSERT_EQ(r.log.time.size(), expected.log.time.size());
  EXPECT_EQ(r.statistics.ticks, 1000);
  EXPECT_EQ(r.statistics.missed_samples, 0);
  const double rmse_sim = expected.metrics.at("tracking_rmse");
  const double rmse_hil = r.metrics.at("tracking_rmse");
  RecordProperty("tracking_rmse_sim_um", std::to_string(rmse_sim * 1e6));
  RecordProperty("tracking_rmse_quanser_um", std::to_string(rmse_hil * 1e6));
  EXPECT_GT(rmse_sim, 10e-6);
  // The tolerances of VirtualStageTest.HilRunReproducesTheSimulatedRun: RMS tracking error within 10 %, the median
  // sample-by-sample position difference below 5 % of it.
  EXPECT_NEAR(rmse_hil, rmse_sim, 0.10 * rmse_sim);
  const double median = testing::MedianAbsoluteDifference(r.log.Column("position"), expected.log.Column("position"));
  RecordProperty("median_position_difference_nm", std::to_string(median * 1e9));
  EXPECT_LT(median, 0.05 * rmse_sim);
}

}  // namespace
}  // namespace mb
