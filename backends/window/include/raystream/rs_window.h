/**
 * @file rs_window.h
 * A window that shows frames (module rs_window, backends/window): X11 + an EGL context on
 * the window surface, and a status strip of its own under the image (two lines). It is a
 * GL context provider like backends/egl: rs_window_renderer_create() gives a GLES renderer
 * (backends/gles) that draws each frame straight into the window, no readback. Frames
 * that come as RGBA8 bytes (remote, CPU, OSMesa) are shown by the same display kernel,
 * scaled into the image area (pixel for pixel at the window's size). Keys are turned into
 * events. One thread; not thread-safe.
 */
#ifndef RS_WINDOW_H
#define RS_WINDOW_H

#include <stdint.h>

#include "raystream/rs_render.h"
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
 * Show an RGBA8 image (row 0 = top) and swap: at the window's size pixel for pixel, a
 * smaller image scaled up to fill the image area (dynamic resolution). The image is kept
 * for redraws on expose. RS_ERR_INVALID for an empty or larger image; RS_ERR_DEVICE when
 * GL fails.
 */
enum rs_status rs_window_present(struct rs_window *window, const uint8_t *rgba, uint32_t width,
                                 uint32_t height, struct rs_error *err);

/**
 * A GLES renderer (rs_gles.h) drawing on this window's context: every rs_renderer_render()
 * also shows the frame in the window (the display kernel writes the default framebuffer
 * and the window swaps); rs_frame outputs are read back only when asked for. `desc` as for
 * rs_renderer_open(). Destroy the renderer before the window.
 */
enum rs_status rs_window_renderer_create(struct rs_window *window,
                                         const struct rs_render_desc *desc,
                                         struct rs_renderer **out, struct rs_error *err);

/** Set the title and the status line drawn in the strip under the image (the viewer's
 * fps / latency / link line; split over two lines at a " | " when it is wider than the
 * window). The image area itself is never drawn over. */
void rs_window_set_title(struct rs_window *window, const char *title);

/** Handle pending X events without blocking; the first key event found, else NONE. */
enum rs_window_event rs_window_poll(struct rs_window *window);

#ifdef __cplusplus
}
#endif
#endif
