#pragma once
// The Quanser backend: an IoBoard on the Quanser HIL C API (hil.h), built when CMake is configured with
// -DWITH_QUANSER=ON and finds the Quanser HIL SDK (cmake/FindHIL.cmake; docs/hil.md, "Quanser boards").
// The sample clock is the board's hardware clock: an encoder reader task (hil_task_create_encoder_reader,
// hil_task_start at 1/period Hz) whose hil_task_read_encoder blocks until the next sample. The board's own
// watchdog (hil_watchdog_set_analog_expiration_state, hil_watchdog_start, reloaded at every write) drives the
// analog outputs to 0 V if the loop stalls — the last resort behind the runner's safe stop.

#include <memory>
#include <string>

#include "hw/board.h"

namespace mb {

struct QuanserBoardOptions {
  std::string board_type = "q8_usb";  ///< hil_open card type: q8_usb, q2_usb, qpid_e, …
  std::string board_identifier = "0";
  int encoder_channels = 1;           ///< encoder channels 0 … n−1 are read at every sample
  int analog_outputs = 1;             ///< analog outputs 0 … n−1 are written at every sample
  int digital_inputs = 0;             ///< digital inputs 0 … n−1 are read at every sample
  int digital_outputs = 0;            ///< digital outputs 0 … n−1 are written at every sample
  double watchdog_timeout = 0.01;     ///< hardware watchdog expiry [s] (outputs go to 0 V)
};

/// True when this build contains the Quanser backend.
bool QuanserBackendAvailable();

/// Opens the board (hil_open). @throws std::runtime_error with the SDK's message, or, in a build without the
/// backend, explaining how to build it (install the SDK, configure with -DWITH_QUANSER=ON).
std::unique_ptr<IoBoard> OpenQuanserBoard(const QuanserBoardOptions& options);

}  // namespace mb
