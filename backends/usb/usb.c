/*
 * USB transport: reads from one bulk/interrupt IN endpoint; bytes go to the stream
 * parser, so frames may span transfers. libusb is reached only through rs_usb_api, whose
 * codes usb_api.c has already translated.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "usb_api.h"

/* Read length when the endpoint's max packet size is unknown: a multiple of every
 * full/high-speed bulk packet size, so a read cannot overflow on those. */
#define USB_READ 512

struct usb {
	const struct rs_usb_api *api;
	void *usb;
	void *handle;
	uint16_t vid, pid;
	int interface;
	uint8_t endpoint;
	int interrupt;
	int packet; /* bytes per read: the endpoint's max packet size, else USB_READ */
};

const char *rs_usb_code_name(int code)
{
	switch (code) {
	case RS_USB_OK:
		return "RS_USB_OK";
	case RS_USB_TIMEOUT:
		return "RS_USB_TIMEOUT";
	case RS_USB_NOT_FOUND:
		return "RS_USB_NOT_FOUND";
	case RS_USB_NO_DEVICE:
		return "RS_USB_NO_DEVICE";
	case RS_USB_IO:
		return "RS_USB_IO";
	case RS_USB_BUSY:
		return "RS_USB_BUSY";
	case RS_USB_ACCESS:
		return "RS_USB_ACCESS";
	}
	return "RS_USB_OTHER";
}

static const char *ename(const struct usb *u, int code)
{
	(void)u;
	return rs_usb_code_name(code);
}

static void usb_close_handle(struct usb *u)
{
	if (!u->handle)
		return;
	u->api->release_interface(u->api->ctx, u->handle, u->interface);
	u->api->close(u->api->ctx, u->handle);
	u->handle = NULL;
}

static enum rs_status usb_open_dev(struct usb *u, struct rs_error *err)
{
	u->handle = u->api->open_vid_pid(u->api->ctx, u->usb, u->vid, u->pid);
	if (!u->handle)
		return rs_error_set(err, RS_ERR_NOT_FOUND,
		                    "usb: no device %04x:%04x (or no access)", u->vid, u->pid);
	int r = u->api->find_in_endpoint(u->api->ctx, u->handle, &u->interface, &u->endpoint,
	                                 &u->interrupt);
	if (r != RS_USB_OK) {
		u->api->close(u->api->ctx, u->handle);
		u->handle = NULL;
		return rs_error_set(err, r == RS_USB_NOT_FOUND ? RS_ERR_UNSUPPORTED : RS_ERR_DEVICE,
		                    "usb: %04x:%04x has no usable IN endpoint (%s)", u->vid, u->pid,
		                    ename(u, r));
	}
	/* One packet per read: a larger read of a device that fills its packets would wait
	 * for several (8 ms for 512 bytes of 64-byte packets at 1 kHz), a smaller one could
	 * overflow on a 1024-byte (SuperSpeed bulk, high-speed interrupt) endpoint. */
	int mps = u->api->max_packet_size
	              ? u->api->max_packet_size(u->api->ctx, u->handle, u->endpoint)
	              : 0;
	u->packet = mps > 0 && mps <= 4096 ? mps : USB_READ;
	r = u->api->claim_interface(u->api->ctx, u->handle, u->interface);
	if (r != RS_USB_OK) {
		u->api->close(u->api->ctx, u->handle);
		u->handle = NULL;
		return rs_error_set(err, RS_ERR_DEVICE, "usb: cannot claim interface %d: %s",
		                    u->interface, ename(u, r));
	}
	return RS_OK;
}

static enum rs_status usb_read(void *impl, uint8_t *buf, size_t cap, int timeout_ms, size_t *out_n,
                               struct rs_error *err)
{
	struct usb *u = impl;
	*out_n = 0;
	if (!u->handle)
		return rs_error_set(err, RS_ERR_DISCONNECTED, "usb: device closed");
	int len = cap < (size_t)u->packet ? (int)cap : u->packet;
	/* libusb reads 0 as "forever"; our 0 means "poll", the closest is 1 ms. */
	unsigned t = timeout_ms < 0 ? 0u : timeout_ms == 0 ? 1u : (unsigned)timeout_ms;
	int got = 0;
	int r =
	    u->api->transfer(u->api->ctx, u->handle, u->endpoint, u->interrupt, buf, len, &got, t);
	if (got < 0 || got > len)
		got = 0;
	if ((r == RS_USB_OK || r == RS_USB_TIMEOUT) && got > 0) {
		*out_n = (size_t)got;
		return RS_OK;
	}
	if (r == RS_USB_OK || r == RS_USB_TIMEOUT)
		return rs_error_set(err, RS_TIMEOUT, "usb: timeout");
	if (r == RS_USB_NO_DEVICE || r == RS_USB_IO) {
		usb_close_handle(u); /* release fails harmlessly on a vanished device */
		return rs_error_set(err, RS_ERR_DISCONNECTED, "usb: %04x:%04x disconnected (%s)",
		                    u->vid, u->pid, ename(u, r));
	}
	return rs_error_set(err, RS_ERR_DEVICE, "usb: transfer failed: %s", ename(u, r));
}

static enum rs_status usb_reopen(void *impl, struct rs_error *err)
{
	struct usb *u = impl;
	usb_close_handle(u);
	return usb_open_dev(u, err);
}

static void usb_destroy(void *impl)
{
	struct usb *u = impl;
	if (!u)
		return;
	usb_close_handle(u);
	if (u->usb)
		u->api->exit(u->api->ctx, u->usb);
	free(u);
}

static const struct rs_track_transport usb_transport = {
    .read = usb_read,
    .reopen = usb_reopen,
    .destroy = usb_destroy,
};

enum rs_status rs_usb_open(const struct rs_usb_desc *desc, struct rs_track_source **out_source,
                           struct rs_error *err)
{
	return rs_usb_open_api(desc, rs_usb_api_default(), out_source, err);
}

enum rs_status rs_usb_open_api(const struct rs_usb_desc *desc, const struct rs_usb_api *api,
                               struct rs_track_source **out_source, struct rs_error *err)
{
	RS_ASSERT(out_source);
	*out_source = NULL;
	RS_ASSERT(desc && api);
	if (desc->vid == 0 && desc->pid == 0)
		return rs_error_set(err, RS_ERR_INVALID, "usb: vendor and product id required");
	struct usb *u = calloc(1, sizeof *u);
	if (!u)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "usb: out of memory");
	u->api = api;
	u->vid = desc->vid;
	u->pid = desc->pid;
	int r = u->api->init(u->api->ctx, &u->usb);
	if (r != RS_USB_OK) {
		rs_error_set(err, RS_ERR_DEVICE, "usb: cannot initialise libusb (%s)", ename(u, r));
		free(u);
		return RS_ERR_DEVICE;
	}
	enum rs_status st = usb_open_dev(u, err);
	if (st != RS_OK) {
		usb_destroy(u);
		return st;
	}
	return rs_track_stream_create(&usb_transport, u, out_source, err);
}

/* 1-4 hex digits and nothing else (strtoul would also take "0x", signs and blanks). */
enum rs_status rs_usb_parse_uri(const char *rest, struct rs_usb_desc *out, struct rs_error *err)
{
	RS_ASSERT(rest && out);
	memset(out, 0, sizeof *out);
	const char *tail;
	if (rs_track_parse_vid_pid(rest, &out->vid, &out->pid, &tail, NULL) != RS_OK ||
	    *tail != '\0')
		return rs_error_set(err, RS_ERR_PARSE,
		                    "usb: expected usb:VID:PID in hex, got 'usb:%.60s'", rest);
	return RS_OK;
}
