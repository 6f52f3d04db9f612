/**
 * @file rs_hid.h
 * HID tracker backend (module rs_hid): one protocol frame per input report (64 bytes,
 * zero-padded; see docs/protocol.md), read through hidapi. The hidapi calls used are
 * reached through struct rs_hid_api, a thin table that mirrors them one to one: the
 * default table calls hidapi, tests pass a fake device.
 */
#ifndef RS_HID_H
#define RS_HID_H

#include <stddef.h>
#include <stdint.h>
#include <wchar.h>

#include "raystream/rs_track.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The hidapi calls the backend makes, with hidapi's semantics; `ctx` is passed back. */
struct rs_hid_api {
	void *ctx;
	/** hid_init(): 0 on success, -1 on error. */
	int (*init)(void *ctx);
	/** hid_open(): a device handle or NULL. `serial` may be NULL. */
	void *(*open)(void *ctx, unsigned short vid, unsigned short pid, const wchar_t *serial);
	/** hid_read_timeout(): bytes read, 0 on timeout, -1 on error (unplugged). */
	int (*read_timeout)(void *ctx, void *dev, unsigned char *data, size_t len, int ms);
	/** hid_close(). */
	void (*close)(void *ctx, void *dev);
	/** hid_error(): message for `dev` (NULL: for the last open), may return NULL. */
	const wchar_t *(*error)(void *ctx, void *dev);
};

/** The table that calls hidapi itself (static storage; never freed). */
const struct rs_hid_api *rs_hid_api_default(void);

/** HID options; vid and pid are required. */
struct rs_hid_desc {
	uint16_t vid, pid;
	const char *serial;           /**< NULL or "": first matching device; ASCII, at most 127
	                                   characters (else RS_ERR_INVALID); copied */
	const struct rs_hid_api *api; /**< NULL: rs_hid_api_default(); must outlive the source */
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
