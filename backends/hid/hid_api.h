/*
 * Private to the hid backend and its tests, never installed: the hidapi calls the backend
 * makes, behind a table so tests can put a fake device in hidapi's place. Only hid_api.c
 * includes hidapi.h.
 */
#ifndef RS_HID_API_H
#define RS_HID_API_H

#include <wchar.h>

#include "raystream/rs_hid.h"

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

/** rs_hid_open() through `api` (which must outlive the source) instead of hidapi. */
enum rs_status rs_hid_open_api(const struct rs_hid_desc *desc, const struct rs_hid_api *api,
                               struct rs_track_source **out_source, struct rs_error *err);

#endif
