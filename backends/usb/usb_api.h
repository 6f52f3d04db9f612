/*
 * Private to the usb backend and its tests, never installed: the libusb calls the backend
 * makes, behind a table so tests can put a fake device in libusb's place. The real table
 * (usb_api.c) translates libusb's return codes into enum rs_usb_code, so usb.c and the
 * tests never see libusb's headers and libusb stays a private dependency.
 */
#ifndef RS_USB_API_H
#define RS_USB_API_H

#include "raystream/rs_usb.h"

/** What a table call returns: 0, or one of these (libusb's codes, translated). */
enum rs_usb_code {
	RS_USB_OK = 0,
	RS_USB_TIMEOUT = -1,   /**< LIBUSB_ERROR_TIMEOUT */
	RS_USB_NOT_FOUND = -2, /**< LIBUSB_ERROR_NOT_FOUND */
	RS_USB_NO_DEVICE = -3, /**< LIBUSB_ERROR_NO_DEVICE */
	RS_USB_IO = -4,        /**< LIBUSB_ERROR_IO */
	RS_USB_BUSY = -5,      /**< LIBUSB_ERROR_BUSY */
	RS_USB_ACCESS = -6,    /**< LIBUSB_ERROR_ACCESS */
	RS_USB_OTHER = -7,     /**< any other libusb error */
};

/** Constant name of a code ("RS_USB_NO_DEVICE"); never NULL. */
const char *rs_usb_code_name(int code);

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
	/** libusb_get_max_packet_size() of `endpoint`: > 0, or an error code. May be NULL
	 *  (reads then ask for 512 bytes). Reads are one packet long, so a device that fills
	 *  its packets is read as each packet lands instead of after several. */
	int (*max_packet_size)(void *ctx, void *handle, uint8_t endpoint);
};

/** The table that calls libusb itself (static storage). */
const struct rs_usb_api *rs_usb_api_default(void);

/** rs_usb_open() through `api` (which must outlive the source) instead of libusb. */
enum rs_status rs_usb_open_api(const struct rs_usb_desc *desc, const struct rs_usb_api *api,
                               struct rs_track_source **out_source, struct rs_error *err);

#endif
