/* A test double of the Quanser HIL C API (hil.h), for building and exercising hw/quanser_board.cc without the
 * Quanser HIL SDK (tests/hw/CMakeLists.txt). Only what the backend calls is declared. The types and signatures
 * are written from Quanser's public HIL SDK documentation (docs.quanser.com, "HIL API": hil_open, hil_task_*,
 * hil_watchdog_*; the SDK's example programs), not copied from the SDK's headers, which are not vendored here
 * (DESIGN.md: the SDK comes from Quanser's repository). The behaviour behind them is tests/hw/fake_hil/fake_hil.h. */
#ifndef MB_FAKE_HIL_H
#define MB_FAKE_HIL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef int t_int;
typedef unsigned int t_uint;
typedef int32_t t_int32;
typedef uint32_t t_uint32;
typedef double t_double;
typedef char t_boolean;
typedef char t_char;
typedef t_int t_error; /* 0 = success, < 0 = an error code (its negation is the documented error number) */

typedef struct tag_card* t_card; /* an open board */
typedef struct tag_task* t_task; /* a task (a buffered, clocked reader or writer) of a board */

/* The clock that paces a task: the board's hardware clocks are 0, 1, …; system clocks are negative. */
typedef enum tag_clock {
  SYSTEM_CLOCK_4 = -4,
  SYSTEM_CLOCK_3 = -3,
  SYSTEM_CLOCK_2 = -2,
  SYSTEM_CLOCK_1 = -1,
  HARDWARE_CLOCK_0 = 0,
  HARDWARE_CLOCK_1,
  HARDWARE_CLOCK_2
} t_clock;

/* Opens the board of type `card_type` ("q8_usb", …) and instance `card_identifier` ("0"). */
t_error hil_open(const char* card_type, const char* card_identifier, t_card* card);
t_error hil_close(t_card card);

/* Sets the encoder counters of `channels` to `buffer` [counts]. */
t_error hil_set_encoder_counts(t_card card, const t_uint32 channels[], t_uint32 num_channels, const t_int32 buffer[]);
/* Writes `buffer` [V] to the analog outputs `channels` immediately. */
t_error hil_write_analog(t_card card, const t_uint32 channels[], t_uint32 num_channels, const t_double buffer[]);
/* Reads / writes digital lines immediately. */
t_error hil_read_digital(t_card card, const t_uint32 channels[], t_uint32 num_channels, t_boolean buffer[]);
t_error hil_write_digital(t_card card, const t_uint32 channels[], t_uint32 num_channels, const t_boolean buffer[]);

/* The board's watchdog: when it expires the analog outputs go to their expiration state. hil_watchdog_reload returns
 * 1 when reloaded in time, 0 when the watchdog had already expired, < 0 on an error. */
t_error hil_watchdog_set_analog_expiration_state(t_card card, const t_uint channels[], t_uint num_channels,
                                                 const t_double voltages[]);
t_error hil_watchdog_start(t_card card, t_double timeout);
t_int hil_watchdog_reload(t_card card);
t_error hil_watchdog_stop(t_card card);
t_error hil_watchdog_clear(t_card card);

/* An encoder reader task: `samples_in_buffer` samples of `channels`, clocked by hil_task_start at `frequency` [Hz]
 * for `num_samples` samples (−1 = until stopped). hil_task_read_encoder blocks until `num_samples` samples are
 * available and returns how many it read (< 0 on an error). */
t_error hil_task_create_encoder_reader(t_card card, t_uint samples_in_buffer, const t_uint32 channels[],
                                       t_uint32 num_channels, t_task* task);
t_error hil_task_start(t_task task, t_clock clock, t_double frequency, t_int num_samples);
t_int hil_task_read_encoder(t_task task, t_uint32 num_samples, t_int32 buffer[]);
t_error hil_task_stop(t_task task);
t_error hil_task_delete(t_task task);

#ifdef __cplusplus
}
#endif

#endif /* MB_FAKE_HIL_H */
