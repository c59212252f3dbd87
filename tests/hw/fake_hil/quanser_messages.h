/* Test double of the Quanser SDK's quanser_messages.h (see hil.h here): the text of an error code. Written from
 * Quanser's public documentation of msg_get_error_message. */
#ifndef MB_FAKE_QUANSER_MESSAGES_H
#define MB_FAKE_QUANSER_MESSAGES_H

#include "hil.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Writes the message of `error_code` (< 0) into `buffer` (NUL-terminated, at most `buffer_size` bytes); `locale`
 * NULL = the default. Returns the message's length, or < 0 on an error. */
t_int msg_get_error_messageA(const t_char* locale, t_error error_code, t_char* buffer, size_t buffer_size);

#ifdef __cplusplus
}
#endif

#endif /* MB_FAKE_QUANSER_MESSAGES_H */
