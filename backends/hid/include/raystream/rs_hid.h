/**
 * @file rs_hid.h
 * HID tracker backend (module rs_hid): one protocol frame per input report (64 bytes,
 * zero-padded; see docs/protocol.md), read through hidapi. hidapi errors are translated
 * inside the backend; nothing here needs hidapi's headers.
 */
#ifndef RS_HID_H
#define RS_HID_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_track.h"

#ifdef __cplusplus
extern "C" {
#endif

/** HID options; vid and pid are required. */
struct rs_hid_desc {
	uint16_t vid, pid;
	const char *serial; /**< NULL or "": first matching device; ASCII, at most 127
	                         characters (else RS_ERR_INVALID); copied */
};

/**
 * Open the device and wrap it as a tracker source. RS_ERR_NOT_FOUND when no such device
 * (message includes hidapi's), RS_ERR_DEVICE when hidapi cannot start. A read error
 * (unplug) reads as RS_ERR_DISCONNECTED; rs_track_source_reopen() opens it again.
 */
enum rs_status rs_hid_open(const struct rs_hid_desc *desc, struct rs_track_source **out_source,
                           struct rs_error *err);

/**
 * Parse the part after "hid:": `VID:PID[:SERIAL]`, VID and PID as 1-4 hex digits. The
 * serial is copied into `serial_buf` (capacity `serial_cap`). RS_ERR_PARSE with a message.
 */
enum rs_status rs_hid_parse_uri(const char *rest, struct rs_hid_desc *out_desc, char *serial_buf,
                                size_t serial_cap, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
