// The test double of the Quanser HIL C API: the functions of hil.h and quanser_messages.h on one simulated board
// (fake_hil.h). Single-threaded, as the backend's loop is.
#include "tests/hw/fake_hil/fake_hil.h"

#include <array>
#include <cmath>
#include <cstdio>

#include "hil.h"
#include "quanser_messages.h"

struct tag_card {
  int unused = 0;
};
struct tag_task {
  int unused = 0;
};

namespace mb::fake_hil {
namespace {

constexpr std::size_t kChannels = 32;

struct Board {
  Plant plant;
  Fault fault = Fault::kNone;
  long at_sample = 0;
  std::vector<CallRecord> record;
  std::size_t capacity = 0;
  long unrecorded = 0;
  bool open = false;
  bool task_created = false;
  bool task_running = false;
  double frequency = 0.0;
  t_uint32 task_channels = 0;  // encoder channels 0 … n−1 of the reader task
  double position = 0.0;
  double velocity = 0.0;
  std::int64_t count_offset = 0;
  std::array<double, kChannels> volts{};
  std::array<double, kChannels> expiration_volts{};
  bool watchdog_running = false;
  bool watchdog_expired = false;
  double watchdog_timeout = 0.0;
  long samples = 0;
  void (*on_first_read)() = nullptr;
  void (*on_task_stop)() = nullptr;
  tag_card card;
  tag_task task;
};

Board& TheBoard() {
  static Board board;
  return board;
}

int Note(Call call, int result, double volts = 0.0) {
  Board& b = TheBoard();
  if (b.record.size() < b.capacity) {
    b.record.push_back(CallRecord{call, result, volts});  // within the reserved capacity: no allocation
  } else {
    ++b.unrecorded;
  }
  return result;
}

double Applied(const Board& b) { return b.watchdog_expired ? b.expiration_volts[0] : b.volts[0]; }

// One sample period T of M ẍ = F − B ẋ with the force F held (exact solution of the linear ODE).
void Advance(Board* b, double T) {
  const double force = b->plant.newtons_per_volt * Applied(*b);
  const double m = b->plant.mass, damping = b->plant.damping;
  if (damping <= 0.0) {
    b->position += b->velocity * T + 0.5 * force / m * T * T;
    b->velocity += force / m * T;
    return;
  }
  const double v_inf = force / damping, decay = std::exp(-damping / m * T);
  b->position += v_inf * T + (b->velocity - v_inf) * (1.0 - decay) * m / damping;
  b->velocity = v_inf + (b->velocity - v_inf) * decay;
}

std::int64_t Counts(const Board& b) { return std::llround(b.position * b.plant.counts_per_metre) - b.count_offset; }

}  // namespace

const char* ToString(Call call) {
  switch (call) {
    case Call::kOpen: return "hil_open";
    case Call::kSetEncoderCounts: return "hil_set_encoder_counts";
    case Call::kWriteAnalog: return "hil_write_analog";
    case Call::kWatchdogSetAnalogExpirationState: return "hil_watchdog_set_analog_expiration_state";
    case Call::kWatchdogStart: return "hil_watchdog_start";
    case Call::kTaskCreateEncoderReader: return "hil_task_create_encoder_reader";
    case Call::kTaskStart: return "hil_task_start";
    case Call::kTaskReadEncoder: return "hil_task_read_encoder";
    case Call::kWatchdogReload: return "hil_watchdog_reload";
    case Call::kReadDigital: return "hil_read_digital";
    case Call::kWriteDigital: return "hil_write_digital";
    case Call::kTaskStop: return "hil_task_stop";
    case Call::kTaskDelete: return "hil_task_delete";
    case Call::kWatchdogStop: return "hil_watchdog_stop";
    case Call::kWatchdogClear: return "hil_watchdog_clear";
    case Call::kClose: return "hil_close";
  }
  return "?";
}

void Reset(const Plant& plant, Fault fault, long at_sample, std::size_t record_capacity) {
  Board& b = TheBoard();
  std::vector<CallRecord> record;
  record.reserve(record_capacity);
  b = Board{};
  b.plant = plant;
  b.fault = fault;
  b.at_sample = at_sample;
  b.record = std::move(record);
  b.capacity = record_capacity;
}

std::vector<CallRecord> Record() { return TheBoard().record; }

std::vector<Call> Calls() {
  std::vector<Call> calls;
  for (const auto& r : TheBoard().record) calls.push_back(r.call);
  return calls;
}

long Unrecorded() { return TheBoard().unrecorded; }
double Position() { return TheBoard().position; }
double Velocity() { return TheBoard().velocity; }
double AppliedVolts() { return Applied(TheBoard()); }
long SamplesRead() { return TheBoard().samples; }
double TaskFrequency() { return TheBoard().frequency; }
double WatchdogTimeout() { return TheBoard().watchdog_timeout; }
bool WatchdogExpired() { return TheBoard().watchdog_expired; }
bool IsOpen() { return TheBoard().open; }

void SetLoopHooks(void (*on_first_read)(), void (*on_task_stop)()) {
  TheBoard().on_first_read = on_first_read;
  TheBoard().on_task_stop = on_task_stop;
}

}  // namespace mb::fake_hil

using mb::fake_hil::Call;
using mb::fake_hil::Fault;
using mb::fake_hil::kInjectedError;
using mb::fake_hil::Note;
using mb::fake_hil::TheBoard;

namespace {

// An error for a call on a board that is not open (or another card's handle): the SDK's "invalid card handle".
constexpr t_error kInvalidHandle = -1;

bool Valid(t_card card) { return TheBoard().open && card == &TheBoard().card; }
bool Valid(t_task task) { return TheBoard().task_created && task == &TheBoard().task; }

}  // namespace

extern "C" {

t_error hil_open(const char*, const char*, t_card* card) {
  auto& b = TheBoard();
  if (b.fault == Fault::kOpenFails) return Note(Call::kOpen, kInjectedError);
  b.open = true;
  *card = &b.card;
  return Note(Call::kOpen, 0);
}

t_error hil_close(t_card card) {
  if (!Valid(card)) return Note(Call::kClose, kInvalidHandle);
  TheBoard().open = false;
  return Note(Call::kClose, 0);
}

t_error hil_set_encoder_counts(t_card card, const t_uint32 channels[], t_uint32 num_channels, const t_int32 buffer[]) {
  if (!Valid(card)) return Note(Call::kSetEncoderCounts, kInvalidHandle);
  auto& b = TheBoard();
  for (t_uint32 i = 0; i < num_channels; ++i) {
    if (channels[i] == 0) b.count_offset = std::llround(b.position * b.plant.counts_per_metre) - buffer[i];
  }
  return Note(Call::kSetEncoderCounts, 0);
}

t_error hil_write_analog(t_card card, const t_uint32 channels[], t_uint32 num_channels, const t_double buffer[]) {
  if (!Valid(card)) return Note(Call::kWriteAnalog, kInvalidHandle);
  auto& b = TheBoard();
  for (t_uint32 i = 0; i < num_channels; ++i) {
    if (channels[i] < b.volts.size()) b.volts[channels[i]] = buffer[i];
  }
  return Note(Call::kWriteAnalog, 0, b.volts[0]);
}

t_error hil_read_digital(t_card card, const t_uint32*, t_uint32 num_channels, t_boolean buffer[]) {
  if (!Valid(card)) return Note(Call::kReadDigital, kInvalidHandle);
  for (t_uint32 i = 0; i < num_channels; ++i) buffer[i] = 0;
  return Note(Call::kReadDigital, 0);
}

t_error hil_write_digital(t_card card, const t_uint32*, t_uint32, const t_boolean*) {
  return Note(Call::kWriteDigital, Valid(card) ? 0 : kInvalidHandle);
}

t_error hil_watchdog_set_analog_expiration_state(t_card card, const t_uint channels[], t_uint num_channels,
                                                 const t_double voltages[]) {
  if (!Valid(card)) return Note(Call::kWatchdogSetAnalogExpirationState, kInvalidHandle);
  auto& b = TheBoard();
  for (t_uint i = 0; i < num_channels; ++i) {
    if (channels[i] < b.expiration_volts.size()) b.expiration_volts[channels[i]] = voltages[i];
  }
  return Note(Call::kWatchdogSetAnalogExpirationState, 0);
}

t_error hil_watchdog_start(t_card card, t_double timeout) {
  if (!Valid(card)) return Note(Call::kWatchdogStart, kInvalidHandle);
  TheBoard().watchdog_running = true;
  TheBoard().watchdog_timeout = timeout;
  return Note(Call::kWatchdogStart, 0);
}

t_int hil_watchdog_reload(t_card card) {
  if (!Valid(card)) return Note(Call::kWatchdogReload, kInvalidHandle);
  return Note(Call::kWatchdogReload, TheBoard().watchdog_expired ? 0 : 1);
}

t_error hil_watchdog_stop(t_card card) {
  if (!Valid(card)) return Note(Call::kWatchdogStop, kInvalidHandle);
  TheBoard().watchdog_running = false;
  return Note(Call::kWatchdogStop, 0);
}

t_error hil_watchdog_clear(t_card card) {
  if (!Valid(card)) return Note(Call::kWatchdogClear, kInvalidHandle);
  TheBoard().watchdog_expired = false;  // the outputs follow the written values again
  return Note(Call::kWatchdogClear, 0);
}

t_error hil_task_create_encoder_reader(t_card card, t_uint samples_in_buffer, const t_uint32*, t_uint32 num_channels,
                                       t_task* task) {
  if (!Valid(card) || samples_in_buffer == 0 || num_channels == 0) {
    return Note(Call::kTaskCreateEncoderReader, kInvalidHandle);
  }
  TheBoard().task_created = true;
  TheBoard().task_channels = num_channels;
  *task = &TheBoard().task;
  return Note(Call::kTaskCreateEncoderReader, 0);
}

t_error hil_task_start(t_task task, t_clock, t_double frequency, t_int) {
  auto& b = TheBoard();
  if (!Valid(task) || !(frequency > 0.0)) return Note(Call::kTaskStart, kInvalidHandle);
  if (b.fault == Fault::kTaskStartFails) return Note(Call::kTaskStart, kInjectedError);
  b.frequency = frequency;
  b.task_running = true;
  return Note(Call::kTaskStart, 0);
}

t_int hil_task_read_encoder(t_task task, t_uint32 num_samples, t_int32 buffer[]) {
  auto& b = TheBoard();
  if (b.samples == 0 && b.on_first_read != nullptr) b.on_first_read();
  if (!Valid(task) || !b.task_running) return Note(Call::kTaskReadEncoder, kInvalidHandle);
  for (t_uint32 s = 0; s < num_samples; ++s) {
    if (b.fault == Fault::kReadTimeout && b.samples + 1 >= b.at_sample)
      return Note(Call::kTaskReadEncoder, kInjectedError);
    if (b.fault == Fault::kWatchdogExpired && b.samples + 1 >= b.at_sample) b.watchdog_expired = b.watchdog_running;
    Advance(&b, 1.0 / b.frequency);
    ++b.samples;
    for (t_uint32 c = 0; c < b.task_channels; ++c) {  // sample-major: channel 0 is the encoder on the plant
      buffer[s * b.task_channels + c] = c == 0 ? static_cast<t_int32>(Counts(b)) : 0;
    }
  }
  return Note(Call::kTaskReadEncoder, static_cast<t_int>(num_samples));
}

t_error hil_task_stop(t_task task) {
  auto& b = TheBoard();
  if (b.on_task_stop != nullptr) b.on_task_stop();
  if (!Valid(task)) return Note(Call::kTaskStop, kInvalidHandle);
  b.task_running = false;
  return Note(Call::kTaskStop, 0);
}

t_error hil_task_delete(t_task task) {
  if (!Valid(task)) return Note(Call::kTaskDelete, kInvalidHandle);
  TheBoard().task_created = false;
  return Note(Call::kTaskDelete, 0);
}

t_int msg_get_error_messageA(const t_char*, t_error error_code, t_char* buffer, size_t buffer_size) {
  const char* text = error_code == kInjectedError ? "fake HIL: injected fault" : "fake HIL: invalid handle";
  return std::snprintf(buffer, buffer_size, "%s", text);
}

}  // extern "C"
