/* The window's private state, shared by window.c (X11: the window, its status strip and
 * keys) and window_gl.c (EGL: the context, the provider for backends/gles, the display). */
#ifndef RS_WINDOW_INTERNAL_H
#define RS_WINDOW_INTERNAL_H

#include <EGL/egl.h>
#include <X11/Xlib.h>

#include "raystream/rs_gles.h"
#include "raystream/rs_window.h"

struct rs_window {
	Display *dpy;
	Window top, win; /* top: image + status strip; win: the GL child showing the image */
	GC gc;
	XFontStruct *font;
	char status[256];
	Atom wm_delete;
	EGLDisplay egl;
	EGLSurface surface;
	EGLContext ctx;
	struct rs_gles_display *display;
	uint8_t *last; /* the last RGBA8 frame shown, redrawn on expose */
	uint32_t last_w, last_h;
	uint32_t width, height;
};

/* window_gl.c: the EGL context on `win` and the display step (made current, then
 * released); the teardown of both; a redraw of the last RGBA8 frame. */
enum rs_status rs_window_gl_create(struct rs_window *w, struct rs_error *err);
void rs_window_gl_destroy(struct rs_window *w);
enum rs_status rs_window_gl_redraw(struct rs_window *w, struct rs_error *err);

#endif
