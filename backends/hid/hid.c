/*
 * HID transport: one input report per read, trimmed to the frame its header announces
 * (the padding of a 64-byte report is not garbage). Every device call goes through
 * struct rs_hid_api so tests can replace hidapi with a fake device.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hid_api.h"

struct hid {
	const struct rs_hid_api *api;
	void *dev;
	uint16_t vid, pid;
	int has_serial;
	wchar_t serial[128];
};

static void api_message(const struct hid *h, void *dev, char *buf, size_t cap)
{
	const wchar_t *w = h->api->error ? h->api->error(h->api->ctx, dev) : NULL;
	size_t i = 0;
	for (; w && w[i] && i + 1 < cap; i++)
		buf[i] = (w[i] > 0 && w[i] < 128) ? (char)w[i] : '?';
	buf[i] = '\0';
	if (i == 0)
		snprintf(buf, cap, "no detail");
}

static enum rs_status hid_open_dev(struct hid *h, struct rs_error *err)
{
	/* hid_init() is idempotent; hid_exit() is process-wide, so it is left to exit time
	 * rather than risk pulling hidapi from under another open device. */
	if (h->api->init && h->api->init(h->api->ctx) != 0)
		return rs_error_set(err, RS_ERR_DEVICE, "hid: cannot initialise hidapi");
	h->dev = h->api->open(h->api->ctx, h->vid, h->pid, h->has_serial ? h->serial : NULL);
	if (!h->dev) {
		char msg[128];
		api_message(h, NULL, msg, sizeof msg);
		return rs_error_set(err, RS_ERR_NOT_FOUND, "hid: cannot open %04x:%04x: %s", h->vid,
		                    h->pid, msg);
	}
	return RS_OK;
}

static enum rs_status hid_read(void *impl, uint8_t *buf, size_t cap, int timeout_ms, size_t *out_n,
                               struct rs_error *err)
{
	struct hid *h = impl;
	*out_n = 0;
	if (!h->dev)
		return rs_error_set(err, RS_ERR_DISCONNECTED, "hid: device closed");
	unsigned char report[RS_PROTO_HID_REPORT_SIZE];
	int n = h->api->read_timeout(h->api->ctx, h->dev, report, sizeof report, timeout_ms);
	if (n == 0)
		return rs_error_set(err, RS_TIMEOUT, "hid: timeout");
	if (n < 0 || (size_t)n > sizeof report) {
		char msg[128];
		api_message(h, h->dev, msg, sizeof msg);
		h->api->close(h->api->ctx, h->dev);
		h->dev = NULL;
		return rs_error_set(err, RS_ERR_DISCONNECTED, "hid: %04x:%04x disconnected: %s",
		                    h->vid, h->pid, msg);
	}
	size_t len = (size_t)n;
	/* A report carries one frame and zero padding: pass only the announced length. */
	if (len >= RS_PROTO_HEADER_SIZE && report[0] == RS_PROTO_SYNC0 &&
	    report[1] == RS_PROTO_SYNC1 && report[3] <= len && report[3] >= RS_PROTO_HEADER_SIZE)
		len = report[3];
	if (len > cap)
		len = cap;
	memcpy(buf, report, len);
	*out_n = len;
	return RS_OK;
}

static enum rs_status hid_reopen(void *impl, struct rs_error *err)
{
	struct hid *h = impl;
	if (h->dev) {
		h->api->close(h->api->ctx, h->dev);
		h->dev = NULL;
	}
	return hid_open_dev(h, err);
}

static void hid_destroy(void *impl)
{
	struct hid *h = impl;
	if (!h)
		return;
	if (h->dev)
		h->api->close(h->api->ctx, h->dev);
	free(h);
}

static const struct rs_track_transport hid_transport = {
    .read = hid_read,
    .reopen = hid_reopen,
    .destroy = hid_destroy,
};

enum rs_status rs_hid_open(const struct rs_hid_desc *desc, struct rs_track_source **out_source,
                           struct rs_error *err)
{
	return rs_hid_open_api(desc, rs_hid_api_default(), out_source, err);
}

enum rs_status rs_hid_open_api(const struct rs_hid_desc *desc, const struct rs_hid_api *api,
                               struct rs_track_source **out_source, struct rs_error *err)
{
	RS_ASSERT(out_source);
	*out_source = NULL;
	RS_ASSERT(desc && api);
	if (desc->vid == 0 && desc->pid == 0)
		return rs_error_set(err, RS_ERR_INVALID, "hid: vendor and product id required");
	/* Widened byte by byte below: a longer (silently cut) or non-ASCII serial could
	 * never match the device's, so say so instead of "not found". */
	if (desc->serial) {
		size_t i = 0;
		for (; desc->serial[i]; i++)
			if ((unsigned char)desc->serial[i] > 127)
				return rs_error_set(err, RS_ERR_INVALID,
				                    "hid: serial number must be ASCII");
		if (i >= sizeof((struct hid *)0)->serial / sizeof(wchar_t))
			return rs_error_set(err, RS_ERR_INVALID,
			                    "hid: serial number longer than %zu characters",
			                    sizeof((struct hid *)0)->serial / sizeof(wchar_t) - 1);
	}
	struct hid *h = calloc(1, sizeof *h);
	if (!h)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "hid: out of memory");
	h->api = api;
	h->vid = desc->vid;
	h->pid = desc->pid;
	if (desc->serial && desc->serial[0]) {
		size_t i = 0;
		for (; desc->serial[i] && i + 1 < sizeof h->serial / sizeof h->serial[0]; i++)
			h->serial[i] = (wchar_t)(unsigned char)desc->serial[i];
		h->serial[i] = 0;
		h->has_serial = 1;
	}
	enum rs_status st = hid_open_dev(h, err);
	if (st != RS_OK) {
		free(h);
		return st;
	}
	return rs_track_stream_create(&hid_transport, h, out_source, err);
}

enum rs_status rs_hid_parse_uri(const char *rest, struct rs_hid_desc *out, char *serial_buf,
                                size_t serial_cap, struct rs_error *err)
{
	RS_ASSERT(rest && out);
	memset(out, 0, sizeof *out);
	const char *tail;
	if (rs_track_parse_vid_pid(rest, &out->vid, &out->pid, &tail, NULL) != RS_OK)
		return rs_error_set(err, RS_ERR_PARSE,
		                    "hid: expected hid:VID:PID[:SERIAL] in hex, got 'hid:%.60s'",
		                    rest);
	if (*tail == ':') {
		const char *ser = tail + 1;
		size_t n = strlen(ser);
		if (n == 0 || !serial_buf || n + 1 > serial_cap)
			return rs_error_set(err, RS_ERR_PARSE,
			                    "hid: empty or too long serial number");
		memcpy(serial_buf, ser, n + 1);
		out->serial = serial_buf;
	}
	return RS_OK;
}
