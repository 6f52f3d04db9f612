/**
 * @file rs_window.h
 * A window that shows frames (module rs_window, backends/window): X11 + an EGL window
 * surface + a GLES 3 textured quad, pixel for pixel (nearest sampling, one texel per
 * pixel, row 0 at the top, at the window's top-left) and a one-line status strip under it.
 * Keys are turned into events. Only shows images: rendering
 * happens elsewhere (rs_render.h). One thread; not thread-safe.
 */
#ifndef RS_WINDOW_H
#define RS_WINDOW_H

#include <stdint.h>

#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Window options; zero means defaults. */
struct rs_window_desc {
	uint32_t width, height; /**< client area = image size; 0 -> 512 */
	const char *title;      /**< NULL -> "raystream" */
	int x, y;               /**< position on the screen (window managers may ignore it) */
	const char *display;    /**< X display name; NULL -> $DISPLAY */
};

/** What rs_window_poll() reports. */
enum rs_window_event {
	RS_WINDOW_NONE = 0,
	RS_WINDOW_QUIT = 1,     /**< q, Escape, or the window was closed */
	RS_WINDOW_SWITCH = 2,   /**< space or m: switch local/remote */
	RS_WINDOW_RECENTRE = 3, /**< r */
};

struct rs_window;

/**
 * Open and map the window and make its GLES 3 context. RS_ERR_DEVICE (with the reason)
 * when there is no display or EGL/GLES 3 cannot start; RS_ERR_INVALID for sizes above
 * the GL's texture limit. Destroy with rs_window_destroy().
 */
enum rs_status rs_window_create(const struct rs_window_desc *desc, struct rs_window **out,
                                struct rs_error *err);

/** Free everything; accepts NULL and sets *window to NULL. */
void rs_window_destroy(struct rs_window **window);

/**
 * Show an RGBA8 image (row 0 = top) of the window's size and swap. The image is kept for
 * redraws on expose. RS_ERR_INVALID for another size; RS_ERR_DEVICE when GL fails.
 */
enum rs_status rs_window_present(struct rs_window *window, const uint8_t *rgba, uint32_t width,
                                 uint32_t height, struct rs_error *err);

/** Set the title and the status line drawn in a strip under the image (the viewer's
 * fps / latency / link line). The image area itself is never drawn over. */
void rs_window_set_title(struct rs_window *window, const char *title);

/** Handle pending X events without blocking; the first key event found, else NONE. */
enum rs_window_event rs_window_poll(struct rs_window *window);

#ifdef __cplusplus
}
#endif
#endif
