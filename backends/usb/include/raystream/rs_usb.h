/**
 * @file rs_usb.h
 * Raw USB tracker backend (module rs_usb) for devices without a HID interface: protocol
 * frames read from the first bulk or interrupt IN endpoint through libusb. libusb errors
 * are translated inside the backend; nothing here needs libusb's headers.
 */
#ifndef RS_USB_H
#define RS_USB_H

#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_track.h"

#ifdef __cplusplus
extern "C" {
#endif

/** USB options; vid and pid are required. */
struct rs_usb_desc {
	uint16_t vid, pid;
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
