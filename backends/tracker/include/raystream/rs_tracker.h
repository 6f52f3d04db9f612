/**
 * @file rs_tracker.h
 * Open any tracker source from a URI (module rs_tracker, above every device backend):
 *
 *   hid:VID:PID[:SERIAL]          hidapi, one frame per input report (hex ids)
 *   usb:VID:PID                   libusb, first bulk/interrupt IN endpoint (hex ids)
 *   serial:/dev/PATH[?baud=N]     termios raw mode, default 115200 baud
 *   sim:[key=value&...]           the simulator (rs_sim.h keys, plus realtime=0|1)
 *   replay:FILE[?realtime=1]      a recording or raw frame dump
 *
 * The result is an rs_track_source (rs_track.h): read, reopen after a disconnect, stats,
 * destroy.
 */
#ifndef RS_TRACKER_H
#define RS_TRACKER_H

#include <stdbool.h>

#include "raystream/rs_track.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Open the source `uri` names. RS_ERR_PARSE for a malformed URI or unknown scheme,
 * RS_ERR_UNSUPPORTED for a scheme whose backend this build lacks, else the backend's
 * status; a one-line message in `err` either way. Destroy with rs_track_source_destroy().
 */
enum rs_status rs_tracker_open(const char *uri, struct rs_track_source **out_source,
                               struct rs_error *err);

/** Nonzero when this build can open `scheme` ("hid", "usb", "serial", "sim", "replay"). */
bool rs_tracker_has_scheme(const char *scheme);

#ifdef __cplusplus
}
#endif
#endif
