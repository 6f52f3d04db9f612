/* The window's GL side: an EGL context on the X11 window surface that backends/gles draws
 * through (rs_window_renderer_create: frames go straight into the default framebuffer),
 * and the display step for frames that arrive as RGBA8 bytes (remote, CPU, OSMesa): the
 * same kernel either way (rs_gles.h). Every GL call goes through entry points loaded with
 * eglGetProcAddress, never a linked libGLESv2 (libOSMesa exports the same gl* names: a
 * linked call could land in the OSMesa context and leave the window black), and the
 * context is made current around each use and released after, so another context on the
 * thread (an OSMesa or headless EGL renderer) never draws into the window or it into them.
 * Nothing here is specific to Mesa: EGL 1.4 with a GLES 3 config is all it asks of a
 * driver (NVIDIA and Mali included). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "window_internal.h"

static enum rs_status make_current(void *p, struct rs_error *err)
{
	struct rs_window *w = p;
	if (!eglMakeCurrent(w->egl, w->surface, w->surface, w->ctx))
		return rs_error_set(err, RS_ERR_DEVICE, "window: eglMakeCurrent failed (0x%04x)",
		                    (unsigned)eglGetError());
	return RS_OK;
}

static void release(void *p)
{
	struct rs_window *w = p;
	eglMakeCurrent(w->egl, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

static void *proc(void *p, const char *name)
{
	(void)p;
	void *f;
	__eglMustCastToProperFunctionPointerType g = eglGetProcAddress(name);
	memcpy(&f, &g, sizeof f); /* ISO C has no object-to-function cast */
	return f;
}

static void describe(const void *p, char *out, size_t cap)
{
	(void)p;
	snprintf(out, cap, "EGL window");
}

static void keep(void *p)
{
	(void)p; /* the window owns its context: rs_window_destroy() ends it */
}

static void target(const void *p, struct rs_gles_display_target *t)
{
	const struct rs_window *w = p;
	*t = (struct rs_gles_display_target){
	    .fb_width = w->width, .fb_height = w->height, .width = w->width, .height = w->height};
}

static enum rs_status swap(void *p, struct rs_error *err)
{
	struct rs_window *w = p;
	if (!eglSwapBuffers(w->egl, w->surface))
		return rs_error_set(err, RS_ERR_DEVICE, "window: eglSwapBuffers failed (0x%04x)",
		                    (unsigned)eglGetError());
	return RS_OK;
}

static const struct rs_gl_context_ops window_ops = {.backend = "egl",
                                                    .make_current = make_current,
                                                    .release = release,
                                                    .get_proc_address = proc,
                                                    .describe = describe,
                                                    .destroy = keep,
                                                    .display_target = target,
                                                    .swap = swap};

enum rs_status rs_window_renderer_create(struct rs_window *w, const struct rs_render_desc *desc,
                                         struct rs_renderer **out, struct rs_error *err)
{
	RS_ASSERT(w && out);
	return rs_gles_renderer_create(&window_ops, w, desc, out, err);
}

enum rs_status rs_window_gl_create(struct rs_window *w, struct rs_error *err)
{
	w->egl = eglGetDisplay((EGLNativeDisplayType)w->dpy);
	if (w->egl == EGL_NO_DISPLAY || !eglInitialize(w->egl, NULL, NULL))
		return rs_error_set(err, RS_ERR_DEVICE,
		                    "window: EGL does not start on this display");
	static const EGLint cfg_attr[] = {EGL_SURFACE_TYPE,
	                                  EGL_WINDOW_BIT,
	                                  EGL_RENDERABLE_TYPE,
	                                  EGL_OPENGL_ES3_BIT,
	                                  EGL_RED_SIZE,
	                                  8,
	                                  EGL_GREEN_SIZE,
	                                  8,
	                                  EGL_BLUE_SIZE,
	                                  8,
	                                  EGL_NONE};
	EGLConfig cfg;
	EGLint n = 0;
	if (!eglBindAPI(EGL_OPENGL_ES_API) || !eglChooseConfig(w->egl, cfg_attr, &cfg, 1, &n) ||
	    n < 1)
		return rs_error_set(err, RS_ERR_DEVICE, "window: no EGL config for GLES 3 windows");
	w->surface = eglCreateWindowSurface(w->egl, cfg, (EGLNativeWindowType)w->win, NULL);
	static const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
	w->ctx = eglCreateContext(w->egl, cfg, EGL_NO_CONTEXT, ctx_attr);
	if (w->surface == EGL_NO_SURFACE || w->ctx == EGL_NO_CONTEXT ||
	    make_current(w, NULL) != RS_OK)
		return rs_error_set(err, RS_ERR_DEVICE,
		                    "window: no GLES 3 context (EGL error 0x%x)",
		                    (unsigned)eglGetError());
	eglSwapInterval(w->egl, 0); /* the frame rate is the renderer's, not the monitor's */
	enum rs_status st = rs_gles_display_create(proc, w, &w->display, err);
	release(w);
	return st;
}

void rs_window_gl_destroy(struct rs_window *w)
{
	if (!w->egl || w->egl == EGL_NO_DISPLAY)
		return;
	if (w->display && make_current(w, NULL) == RS_OK)
		rs_gles_display_destroy(&w->display);
	release(w);
	if (w->ctx)
		eglDestroyContext(w->egl, w->ctx);
	if (w->surface)
		eglDestroySurface(w->egl, w->surface);
	eglTerminate(w->egl);
}

enum rs_status rs_window_gl_redraw(struct rs_window *w, struct rs_error *err)
{
	struct rs_gles_display_target t;
	target(w, &t);
	enum rs_status st = make_current(w, err);
	if (st != RS_OK)
		return st;
	st = rs_gles_display_rgba8(w->display, w->last, w->last_w, w->last_h, &t, err);
	if (st == RS_OK)
		st = swap(w, err);
	release(w);
	return st;
}

enum rs_status rs_window_present(struct rs_window *w, const uint8_t *rgba, uint32_t width,
                                 uint32_t height, struct rs_error *err)
{
	RS_ASSERT(w && rgba);
	if (!width || !height || width > w->width || height > w->height)
		return rs_error_set(err, RS_ERR_INVALID, "window: frame %ux%u in a %ux%u window",
		                    width, height, w->width, w->height);
	if (width != w->last_w || height != w->last_h) {
		uint8_t *b = realloc(w->last, (size_t)width * height * 4u);
		if (!b)
			return rs_error_set(err, RS_ERR_NO_MEMORY, "window: out of memory");
		w->last = b;
		w->last_w = width;
		w->last_h = height;
	}
	memcpy(w->last, rgba, (size_t)width * height * 4u);
	return rs_window_gl_redraw(w, err);
}
