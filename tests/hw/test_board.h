#pragma once
// An in-process IoBoard for unit tests of the HIL runner's logic (no clock, no sockets): its "plant" is a
// unit mass driven by the analog output, integrated over one period per sample, and it can be told to report
// missed samples or overruns. The user-facing no-hardware path is the virtual stage, tested separately.

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include "hw/board.h"
#include "hw/realtime.h"

namespace mb::testing {

class TestBoard final : public IoBoard {
 public:
  enum class Fault { kNone, kMissAfter, kOverrunAfter };

  TestBoard(Fault fault = Fault::kNone, long long after = 0) : fault_(fault), after_(after) {}

  std::string description() const override { return "test board"; }
  int num_encoder_channels() const override { return 2; }
  int num_analog_outputs() const override { return 2; }

  void Start(double period) override {
    period_ = period;
    started_ = true;
  }
  SampleStatus WaitForSample(SampleTiming* timing) noexcept override {
    if (on_first_sample && samples_ == 0) on_first_sample();
    ++samples_;
    const std::int64_t now = MonotonicNanoseconds();
    timing->wake_ns = now;
    timing->scheduled_ns = now;
    if (fault_ == Fault::kOverrunAfter && samples_ > after_) {
      timing->scheduled_ns = now - static_cast<std::int64_t>(10 * period_ * 1e9);  // far behind schedule
    }
    if (fault_ == Fault::kMissAfter && samples_ > after_) return SampleStatus::kMissed;
    // Unit mass, force = 1 N/V · v, semi-implicit Euler over one period; encoder at 1e7 counts/m.
    velocity_ += analog_outputs_[0] * period_;
    position_ += velocity_ * period_;
    encoder_counts_[0] = static_cast<std::int32_t>(std::lround(position_ * 1e7));
    return SampleStatus::kOk;
  }
  bool WriteOutputs() noexcept override {
    ++writes_;
    return true;
  }
  void SafeStop() noexcept override {
    ZeroOutputImage();
    ++safe_stops_;
    if (on_safe_stop) on_safe_stop();
  }

  std::function<void()> on_first_sample;  // set before the run (called inside the loop: must not allocate)
  std::function<void()> on_safe_stop;
  long long samples() const { return samples_; }
  long long writes() const { return writes_; }
  int safe_stops() const { return safe_stops_; }
  bool started() const { return started_; }

 private:
  Fault fault_;
  long long after_;
  double period_ = 1e-3;
  double position_ = 0.0;
  double velocity_ = 0.0;
  long long samples_ = 0;
  long long writes_ = 0;
  int safe_stops_ = 0;
  bool started_ = false;
};

}  // namespace mb::testing
