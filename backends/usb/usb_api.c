/*
 * The real rs_usb_api: each entry is the libusb call it is named after (the endpoint
 * search walks the active configuration descriptor, the one place with some logic), its
 * return code translated into enum rs_usb_code: the only file that includes libusb.h.
 */
#include <libusb.h>

#include "usb_api.h"

static int code(int r)
{
	if (r >= 0)
		return r; /* success, or a count (max packet size) */
	switch (r) {
	case LIBUSB_ERROR_TIMEOUT:
		return RS_USB_TIMEOUT;
	case LIBUSB_ERROR_NOT_FOUND:
		return RS_USB_NOT_FOUND;
	case LIBUSB_ERROR_NO_DEVICE:
		return RS_USB_NO_DEVICE;
	case LIBUSB_ERROR_IO:
		return RS_USB_IO;
	case LIBUSB_ERROR_BUSY:
		return RS_USB_BUSY;
	case LIBUSB_ERROR_ACCESS:
		return RS_USB_ACCESS;
	default:
		return RS_USB_OTHER;
	}
}

static int real_init(void *ctx, void **out_usb)
{
	(void)ctx;
	libusb_context *c = NULL;
	int r = libusb_init(&c);
	*out_usb = c;
	return code(r);
}

static void real_exit(void *ctx, void *usb)
{
	(void)ctx;
	libusb_exit(usb);
}

static void *real_open(void *ctx, void *usb, uint16_t vid, uint16_t pid)
{
	(void)ctx;
	return libusb_open_device_with_vid_pid(usb, vid, pid);
}

static int real_find(void *ctx, void *handle, int *out_interface, uint8_t *out_endpoint,
                     int *out_interrupt)
{
	(void)ctx;
	struct libusb_config_descriptor *cfg = NULL;
	int r = libusb_get_active_config_descriptor(libusb_get_device(handle), &cfg);
	if (r != LIBUSB_SUCCESS)
		return code(r);
	r = LIBUSB_ERROR_NOT_FOUND;
	for (int i = 0; i < cfg->bNumInterfaces && r != LIBUSB_SUCCESS; i++) {
		const struct libusb_interface *itf = &cfg->interface[i];
		for (int a = 0; a < itf->num_altsetting && r != LIBUSB_SUCCESS; a++) {
			const struct libusb_interface_descriptor *d = &itf->altsetting[a];
			for (int e = 0; e < d->bNumEndpoints; e++) {
				const struct libusb_endpoint_descriptor *ep = &d->endpoint[e];
				int type = ep->bmAttributes & LIBUSB_TRANSFER_TYPE_MASK;
				if (!(ep->bEndpointAddress & LIBUSB_ENDPOINT_IN) ||
				    (type != LIBUSB_TRANSFER_TYPE_BULK &&
				     type != LIBUSB_TRANSFER_TYPE_INTERRUPT))
					continue;
				*out_interface = d->bInterfaceNumber;
				*out_endpoint = ep->bEndpointAddress;
				*out_interrupt = type == LIBUSB_TRANSFER_TYPE_INTERRUPT;
				r = LIBUSB_SUCCESS;
				break;
			}
		}
	}
	libusb_free_config_descriptor(cfg);
	return code(r);
}

static int real_claim(void *ctx, void *handle, int interface)
{
	(void)ctx;
	libusb_set_auto_detach_kernel_driver(handle, 1); /* unsupported on some OSes: fine */
	return code(libusb_claim_interface(handle, interface));
}

static int real_transfer(void *ctx, void *handle, uint8_t endpoint, int interrupt,
                         unsigned char *data, int len, int *out_transferred, unsigned timeout_ms)
{
	(void)ctx;
	return code(interrupt ? libusb_interrupt_transfer(handle, endpoint, data, len,
	                                                  out_transferred, timeout_ms)
	                      : libusb_bulk_transfer(handle, endpoint, data, len, out_transferred,
	                                             timeout_ms));
}

static void real_release(void *ctx, void *handle, int interface)
{
	(void)ctx;
	libusb_release_interface(handle, interface);
}

static void real_close(void *ctx, void *handle)
{
	(void)ctx;
	libusb_close(handle);
}

static int real_max_packet_size(void *ctx, void *handle, uint8_t endpoint)
{
	(void)ctx;
	return code(libusb_get_max_packet_size(libusb_get_device(handle), endpoint));
}

const struct rs_usb_api *rs_usb_api_default(void)
{
	static const struct rs_usb_api api = {
	    .init = real_init,
	    .exit = real_exit,
	    .open_vid_pid = real_open,
	    .find_in_endpoint = real_find,
	    .claim_interface = real_claim,
	    .transfer = real_transfer,
	    .release_interface = real_release,
	    .close = real_close,
	    .max_packet_size = real_max_packet_size,
	};
	return &api;
}
