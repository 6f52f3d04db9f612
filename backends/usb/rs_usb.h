/**
 * @file rs_usb.h
 * Raw USB tracker backend (module rs_usb) for devices without a HID interface: protocol
 * frames read from the first bulk or interrupt IN endpoint through libusb. The libusb
 * calls go through struct rs_usb_api, a thin table mirroring them (libusb's return
 * codes, LIBUSB_SUCCESS / LIBUSB_ERROR_*): the default calls libusb, tests pass a fake.
 */
#ifndef RS_USB_H
#define RS_USB_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_track.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The libusb calls the backend makes; `ctx` is passed back, handles are opaque. */
struct rs_usb_api {
	void *ctx;
	/** libusb_init(): 0 and a context in *out_usb, or an error code. */
	int (*init)(void *ctx, void **out_usb);
	/** libusb_exit(). */
	void (*exit)(void *ctx, void *usb);
	/** libusb_open_device_with_vid_pid(): a handle or NULL. */
	void *(*open_vid_pid)(void *ctx, void *usb, uint16_t vid, uint16_t pid);
	/** Walk libusb_get_active_config_descriptor() for the first IN endpoint of type bulk or
	 *  interrupt: 0 and its interface, address and kind (1 = interrupt), or an error. */
	int (*find_in_endpoint)(void *ctx, void *handle, int *out_interface, uint8_t *out_endpoint,
	                        int *out_interrupt);
	/** libusb_set_auto_detach_kernel_driver() + libusb_claim_interface(). */
	int (*claim_interface)(void *ctx, void *handle, int interface);
	/** libusb_interrupt_transfer() or libusb_bulk_transfer() on an IN endpoint;
	 *  `timeout_ms` 0 means forever (libusb's convention). */
	int (*transfer)(void *ctx, void *handle, uint8_t endpoint, int interrupt,
	                unsigned char *data, int len, int *out_transferred, unsigned timeout_ms);
	/** libusb_release_interface(). */
	void (*release_interface)(void *ctx, void *handle, int interface);
	/** libusb_close(). */
	void (*close)(void *ctx, void *handle);
	/** libusb_error_name(); may be NULL. */
	const char *(*error_name)(void *ctx, int code);
	/** libusb_get_max_packet_size() of `endpoint`: > 0, or an error code. May be NULL
	 *  (reads then ask for 512 bytes). Reads are one packet long, so a device that fills
	 *  its packets is read as each packet lands instead of after several. */
	int (*max_packet_size)(void *ctx, void *handle, uint8_t endpoint);
};

/** The table that calls libusb itself (static storage). */
const struct rs_usb_api *rs_usb_api_default(void);

/** USB options; vid and pid are required. */
struct rs_usb_desc {
	uint16_t vid, pid;
	const struct rs_usb_api *api; /**< NULL: rs_usb_api_default(); must outlive the source */
};

/**
 * Open the device, claim the interface of its first bulk/interrupt IN endpoint and wrap
 * it as a tracker source. RS_ERR_NOT_FOUND (no device), RS_ERR_UNSUPPORTED (no IN
 * endpoint), RS_ERR_DEVICE (libusb failure; message names the libusb error).
 * Unplugging reads as RS_ERR_DISCONNECTED; rs_track_source_reopen() opens it again.
 */
enum rs_status rs_usb_open(const struct rs_usb_desc *desc, struct rs_track_source **out_source,
                           struct rs_error *err);

/** Parse the part after "usb:": `VID:PID` in hex (1-4 digits each). RS_ERR_PARSE. */
enum rs_status rs_usb_parse_uri(const char *rest, struct rs_usb_desc *out_desc,
                                struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
