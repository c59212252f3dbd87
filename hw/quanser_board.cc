#include "hw/quanser_board.h"

#include <stdexcept>

#include <fmt/format.h>

#ifdef MB_WITH_QUANSER
#include <array>
#include <cmath>
#include <cstdint>

#include "hil.h"
#include "quanser_messages.h"

#include "hw/realtime.h"
#endif

namespace mb {

#ifdef MB_WITH_QUANSER

namespace {

std::string HilMessage(t_error code) {
  char text[512] = {};
  msg_get_error_messageA(nullptr, code, text, sizeof text);
  return fmt::format("{} (Quanser error {})", text, -code);
}

/// The Quanser HIL C API sequence of DESIGN.md: hil_open → set encoder counts and the watchdog's expiration
/// state → hil_task_create_encoder_reader → hil_task_start → loop {hil_task_read_encoder; hil_write_analog;
/// hil_watchdog_reload} → hil_task_stop, hil_task_delete, hil_watchdog_stop, hil_close.
class QuanserBoard final : public IoBoard {
 public:
  explicit QuanserBoard(const QuanserBoardOptions& options) : options_(options) {
    if (options_.encoder_channels < 1 || options_.encoder_channels > kMaxEncoderChannels ||
        options_.analog_outputs < 0 || options_.analog_outputs > kMaxAnalogOutputs ||
        options_.digital_inputs < 0 || options_.digital_inputs > kMaxDigitalChannels ||
        options_.digital_outputs < 0 || options_.digital_outputs > kMaxDigitalChannels) {
      throw std::invalid_argument(fmt::format("Quanser board: channel counts must be 1–{} encoders, 0–{} analog "
                                              "outputs, 0–{} digital inputs and outputs",
                                              kMaxEncoderChannels, kMaxAnalogOutputs, kMaxDigitalChannels));
    }
    for (t_uint32 i = 0; i < channels_.size(); ++i) channels_[i] = i;
    const t_error result = hil_open(options_.board_type.c_str(), options_.board_identifier.c_str(), &card_);
    if (result < 0) {
      throw std::runtime_error(fmt::format("hil_open({}, {}): {}; check the cable, the driver and the board type "
                                           "(--quanser-board)",
                                           options_.board_type, options_.board_identifier, HilMessage(result)));
    }
  }

  ~QuanserBoard() override {
    SafeStop();
    hil_close(card_);
  }

  std::string description() const override {
    return fmt::format("quanser {} {}", options_.board_type, options_.board_identifier);
  }
  int num_encoder_channels() const override { return options_.encoder_channels; }
  int num_analog_outputs() const override { return options_.analog_outputs; }

  void Start(double period) override {
    if (!(period > 0.0)) throw std::invalid_argument(fmt::format("Quanser board: period {} s must be > 0", period));
    const auto n_enc = static_cast<t_uint32>(options_.encoder_channels);
    const auto n_ao = static_cast<t_uint32>(options_.analog_outputs);
    std::array<t_int32, kMaxEncoderChannels> zero_counts{};
    std::array<t_double, kMaxAnalogOutputs> zero_volts{};
    Check(hil_set_encoder_counts(card_, channels_.data(), n_enc, zero_counts.data()), "hil_set_encoder_counts");
    if (n_ao > 0) {
      Check(hil_write_analog(card_, channels_.data(), n_ao, zero_volts.data()), "hil_write_analog");
      Check(hil_watchdog_set_analog_expiration_state(card_, channels_.data(), n_ao, zero_volts.data()),
            "hil_watchdog_set_analog_expiration_state");
      Check(hil_watchdog_start(card_, options_.watchdog_timeout), "hil_watchdog_start");
      watchdog_running_ = true;
    }
    // A one-second buffer: if the loop falls behind, samples queue up (and show as overruns) instead of
    // being lost.
    const auto buffer = static_cast<t_uint32>(std::max(2.0, std::round(1.0 / period)));
    Check(hil_task_create_encoder_reader(card_, buffer, channels_.data(), n_enc, &task_),
          "hil_task_create_encoder_reader");
    task_created_ = true;
    Check(hil_task_start(task_, HARDWARE_CLOCK_0, 1.0 / period, -1), "hil_task_start");
    task_running_ = true;
    encoder_counts_.fill(0);
    ZeroOutputImage();
    period_ns_ = static_cast<std::int64_t>(std::llround(period * 1e9));
    start_ns_ = MonotonicNanoseconds();
    sample_ = 0;
  }

  SampleStatus WaitForSample(SampleTiming* timing) noexcept override {
    if (!task_running_) return SampleStatus::kFault;
    ++sample_;
    timing->scheduled_ns = start_ns_ + sample_ * period_ns_;
    std::array<t_int32, kMaxEncoderChannels> counts{};
    const t_int read = hil_task_read_encoder(task_, 1, counts.data());  // blocks until the next sample
    timing->wake_ns = MonotonicNanoseconds();
    if (read < 0) return SampleStatus::kFault;
    if (read == 0) return SampleStatus::kMissed;
    for (int i = 0; i < options_.encoder_channels; ++i) encoder_counts_[Index(i)] = counts[Index(i)];
    if (options_.digital_inputs > 0) {
      std::array<t_boolean, kMaxDigitalChannels> bits{};
      if (hil_read_digital(card_, channels_.data(), static_cast<t_uint32>(options_.digital_inputs), bits.data()) < 0) {
        return SampleStatus::kFault;
      }
      std::uint32_t word = 0;
      for (int i = 0; i < options_.digital_inputs; ++i) word |= (bits[Index(i)] ? 1u : 0u) << i;
      digital_inputs_ = word;
    }
    return SampleStatus::kOk;
  }

  bool WriteOutputs() noexcept override {
    if (options_.analog_outputs > 0 &&
        hil_write_analog(card_, channels_.data(), static_cast<t_uint32>(options_.analog_outputs),
                         analog_outputs_.data()) < 0) {
      return false;
    }
    if (options_.digital_outputs > 0) {
      std::array<t_boolean, kMaxDigitalChannels> bits{};
      for (int i = 0; i < options_.digital_outputs; ++i) bits[Index(i)] = ((digital_outputs_ >> i) & 1u) != 0;
      if (hil_write_digital(card_, channels_.data(), static_cast<t_uint32>(options_.digital_outputs), bits.data()) <
          0) {
        return false;
      }
    }
    // hil_watchdog_reload returns 1 when reloaded, 0 when the watchdog had already expired.
    return !watchdog_running_ || hil_watchdog_reload(card_) == 1;
  }

  void SafeStop() noexcept override {
    ZeroOutputImage();
    std::array<t_double, kMaxAnalogOutputs> zero_volts{};
    if (options_.analog_outputs > 0) {
      hil_write_analog(card_, channels_.data(), static_cast<t_uint32>(options_.analog_outputs), zero_volts.data());
    }
    if (options_.digital_outputs > 0) {
      std::array<t_boolean, kMaxDigitalChannels> low{};
      hil_write_digital(card_, channels_.data(), static_cast<t_uint32>(options_.digital_outputs), low.data());
    }
    if (task_running_) hil_task_stop(task_);
    if (task_created_) hil_task_delete(task_);
    task_running_ = task_created_ = false;
    if (watchdog_running_) {
      hil_watchdog_stop(card_);
      hil_watchdog_clear(card_);
      watchdog_running_ = false;
    }
  }

 private:
  void Check(t_error result, const char* function) {
    if (result < 0) {
      SafeStop();
      throw std::runtime_error(fmt::format("{} on {}: {}", function, description(), HilMessage(result)));
    }
  }

  QuanserBoardOptions options_;
  std::array<t_uint32, kMaxDigitalChannels> channels_{};  // 0, 1, 2, … (channel lists of every call)
  t_card card_{};
  t_task task_{};
  bool task_created_ = false;
  bool task_running_ = false;
  bool watchdog_running_ = false;
  std::int64_t period_ns_ = 0;
  std::int64_t start_ns_ = 0;
  std::int64_t sample_ = 0;
};

}  // namespace

bool QuanserBackendAvailable() { return true; }

std::unique_ptr<IoBoard> OpenQuanserBoard(const QuanserBoardOptions& options) {
  return std::make_unique<QuanserBoard>(options);
}

#else  // built without the Quanser HIL SDK

bool QuanserBackendAvailable() { return false; }

std::unique_ptr<IoBoard> OpenQuanserBoard(const QuanserBoardOptions& options) {
  throw std::runtime_error(fmt::format(
      "--board quanser ({} {}): this motionblocks was built without the Quanser backend; install the Quanser HIL "
      "SDK and configure with -DWITH_QUANSER=ON (docs/hil.md), or use --board udp with `motionblocks "
      "virtual-stage`",
      options.board_type, options.board_identifier));
}

#endif

}  // namespace mb
