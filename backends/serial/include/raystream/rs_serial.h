/**
 * @file rs_serial.h
 * Serial tracker backend (module rs_serial): protocol frames over a termios line in raw
 * mode, read with poll() and timeouts. Also a pseudo-terminal pair (posix_openpt) whose
 * slave side opens like a serial device, so tests and benchmarks can feed the serial
 * path end to end without hardware.
 */
#ifndef RS_SERIAL_H
#define RS_SERIAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_track.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Serial options; zero = defaults. */
struct rs_serial_desc {
	const char *path; /**< device path, e.g. "/dev/ttyUSB0" (required; copied) */
	int baud;         /**< line speed, default 115200; must be a standard rate */
};

/**
 * Open the line and wrap it as a tracker source (rs_track.h). RS_ERR_NOT_FOUND (no such
 * device), RS_ERR_INVALID (not a terminal, unsupported baud), RS_ERR_IO otherwise.
 * A line that hangs up reads as RS_ERR_DISCONNECTED; rs_track_source_reopen() opens the
 * same path again. Destroy with rs_track_source_destroy().
 */
enum rs_status rs_serial_open(const struct rs_serial_desc *desc,
                              struct rs_track_source **out_source, struct rs_error *err);

/**
 * Parse the part after "serial:": `/dev/PATH[?baud=N]`. The path is copied into
 * `path_buf` (capacity `path_cap`) and out_desc->path points there. RS_ERR_PARSE with a
 * message for an empty or relative path, unknown option or bad number.
 */
enum rs_status rs_serial_parse_uri(const char *rest, char *path_buf, size_t path_cap,
                                   struct rs_serial_desc *out_desc, struct rs_error *err);

/** True when `baud` is a rate this build can set. */
bool rs_serial_is_baud_supported(int baud);

/** A pseudo-terminal pair: write to the master, open the slave path as a serial line. */
struct rs_serial_pty;

/** Create a raw-mode pty pair. Destroy with rs_serial_pty_destroy(). */
enum rs_status rs_serial_pty_create(struct rs_serial_pty **out_pty, struct rs_error *err);

/** The slave device path (owned by the pty). */
const char *rs_serial_pty_path(const struct rs_serial_pty *pty);

/** Write all `len` bytes to the master side (blocking until the line takes them). */
enum rs_status rs_serial_pty_write(struct rs_serial_pty *pty, const uint8_t *data, size_t len,
                                   struct rs_error *err);

/**
 * As rs_serial_pty_write(), but waits at most `timeout_ms` (< 0: for ever) for room while
 * the line is full (nobody reads the slave). `*out_written` (may be NULL) receives the
 * bytes taken. RS_OK when all were written, RS_TIMEOUT when the line stayed full (write
 * the rest later to keep the frame whole), RS_ERR_DISCONNECTED / RS_ERR_IO otherwise.
 */
enum rs_status rs_serial_pty_write_timeout(struct rs_serial_pty *pty, const uint8_t *data,
                                           size_t len, int timeout_ms, size_t *out_written,
                                           struct rs_error *err);

/** Close the master side only: readers of the slave see a hang-up (disconnect). */
void rs_serial_pty_hangup(struct rs_serial_pty *pty);

/** Close everything and free `*pty` (NULL allowed); sets it to NULL. */
void rs_serial_pty_destroy(struct rs_serial_pty **pty);

#ifdef __cplusplus
}
#endif
#endif
