/* X11 window + EGL window surface + GLES 3 quad: shows finished frames pixel for pixel. */
#include <EGL/egl.h>
#include <GLES3/gl3.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_window.h"

/* Height of the strip under the image that shows the status line (X core font). */
#define STATUS_STRIP 18

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
	GLuint program, texture, vao;
	uint32_t width, height;
	int have_frame;
};

/* A full-window quad from gl_VertexID alone (no buffers); v flips so row 0 is the top. */
static const char *vs_src = "#version 300 es\n"
                            "out vec2 uv;\n"
                            "void main() {\n"
                            "  vec2 p = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));\n"
                            "  uv = vec2(p.x, 1.0 - p.y);\n"
                            "  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n"
                            "}\n";
static const char *fs_src = "#version 300 es\n"
                            "precision mediump float;\n"
                            "in vec2 uv;\n"
                            "uniform sampler2D image;\n"
                            "out vec4 color;\n"
                            "void main() { color = vec4(texture(image, uv).rgb, 1.0); }\n";

static GLuint compile(GLenum type, const char *src, char *log, size_t cap)
{
	GLuint s = glCreateShader(type);
	glShaderSource(s, 1, &src, NULL);
	glCompileShader(s);
	GLint ok = 0;
	glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
	if (!ok) {
		glGetShaderInfoLog(s, (GLsizei)cap, NULL, log);
		glDeleteShader(s);
		return 0;
	}
	return s;
}

static enum rs_status make_gl(struct rs_window *w, struct rs_error *err)
{
	char log[256] = "";
	GLuint vs = compile(GL_VERTEX_SHADER, vs_src, log, sizeof log);
	GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, fs_src, log, sizeof log) : 0;
	if (!vs || !fs)
		return rs_error_set(err, RS_ERR_DEVICE, "window: shader: %s", log);
	w->program = glCreateProgram();
	glAttachShader(w->program, vs);
	glAttachShader(w->program, fs);
	glLinkProgram(w->program);
	glDeleteShader(vs);
	glDeleteShader(fs);
	GLint ok = 0;
	glGetProgramiv(w->program, GL_LINK_STATUS, &ok);
	if (!ok)
		return rs_error_set(err, RS_ERR_DEVICE, "window: shader program does not link");
	GLint max_side = 0;
	glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_side);
	if ((GLint)w->width > max_side || (GLint)w->height > max_side)
		return rs_error_set(err, RS_ERR_INVALID, "window: %ux%u exceeds the GL's %d texels",
		                    w->width, w->height, max_side);
	glGenVertexArrays(1, &w->vao);
	glGenTextures(1, &w->texture);
	glBindTexture(GL_TEXTURE_2D, w->texture);
	/* nearest + one texel per pixel: the window shows exactly the frame's bytes */
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
	glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, (GLsizei)w->width, (GLsizei)w->height, 0, GL_RGBA,
	             GL_UNSIGNED_BYTE, NULL);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
	if (glGetError() != GL_NO_ERROR)
		return rs_error_set(err, RS_ERR_DEVICE, "window: GL setup failed");
	return RS_OK;
}

static enum rs_status make_egl(struct rs_window *w, struct rs_error *err)
{
	w->egl = eglGetDisplay((EGLNativeDisplayType)w->dpy);
	EGLint major = 0, minor = 0;
	if (w->egl == EGL_NO_DISPLAY || !eglInitialize(w->egl, &major, &minor))
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
	    !eglMakeCurrent(w->egl, w->surface, w->surface, w->ctx))
		return rs_error_set(err, RS_ERR_DEVICE,
		                    "window: no GLES 3 context (EGL error 0x%x)",
		                    (unsigned)eglGetError());
	eglSwapInterval(w->egl, 0); /* the frame rate is the stream's, not the monitor's */
	return RS_OK;
}

enum rs_status rs_window_create(const struct rs_window_desc *desc, struct rs_window **out,
                                struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	struct rs_window_desc d = {0};
	if (desc)
		d = *desc;
	if (!d.width)
		d.width = 512;
	if (!d.height)
		d.height = 512;
	if (d.width > 16384 || d.height > 16384)
		return rs_error_set(err, RS_ERR_INVALID, "window: %ux%u is too large", d.width,
		                    d.height);
	struct rs_window *w = calloc(1, sizeof *w);
	if (!w)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "window: out of memory");
	w->width = d.width;
	w->height = d.height;
	w->dpy = XOpenDisplay(d.display);
	if (!w->dpy) {
		rs_window_destroy(&w);
		return rs_error_set(err, RS_ERR_DEVICE, "window: cannot open X display '%s'",
		                    d.display ? d.display
		                              : (getenv("DISPLAY") ? getenv("DISPLAY") : ""));
	}
	int scr = DefaultScreen(w->dpy);
	unsigned long black = BlackPixel(w->dpy, scr), white = WhitePixel(w->dpy, scr);
	w->top = XCreateSimpleWindow(w->dpy, RootWindow(w->dpy, scr), d.x, d.y, d.width,
	                             d.height + STATUS_STRIP, 0, black, black);
	w->win = XCreateSimpleWindow(w->dpy, w->top, 0, 0, d.width, d.height, 0, black, black);
	/* a fixed size: one texel per pixel */
	XSizeHints hints = {.flags = PMinSize | PMaxSize | PPosition,
	                    .x = d.x,
	                    .y = d.y,
	                    .min_width = (int)d.width,
	                    .max_width = (int)d.width,
	                    .min_height = (int)d.height + STATUS_STRIP,
	                    .max_height = (int)d.height + STATUS_STRIP};
	XSetWMNormalHints(w->dpy, w->top, &hints);
	XStoreName(w->dpy, w->top, d.title ? d.title : "raystream");
	w->wm_delete = XInternAtom(w->dpy, "WM_DELETE_WINDOW", False);
	XSetWMProtocols(w->dpy, w->top, &w->wm_delete, 1);
	XSelectInput(w->dpy, w->top, KeyPressMask | ExposureMask | StructureNotifyMask);
	XSelectInput(w->dpy, w->win, KeyPressMask | ExposureMask | StructureNotifyMask);
	/* the status line: the X core "fixed" font (every X server has it); none, no text */
	w->font = XLoadQueryFont(w->dpy, "fixed");
	w->gc = XCreateGC(w->dpy, w->top, 0, NULL);
	XSetForeground(w->dpy, w->gc, white);
	if (w->font)
		XSetFont(w->dpy, w->gc, w->font->fid);
	XMapWindow(w->dpy, w->win);
	XMapWindow(w->dpy, w->top);
	for (XEvent e;;) { /* drawing before the map would be lost */
		XNextEvent(w->dpy, &e);
		if (e.type == MapNotify && e.xmap.window == w->top)
			break;
	}
	enum rs_status st = make_egl(w, err);
	if (st == RS_OK)
		st = make_gl(w, err);
	if (st != RS_OK) {
		rs_window_destroy(&w);
		return st;
	}
	glViewport(0, 0, (GLsizei)w->width, (GLsizei)w->height);
	glClearColor(0, 0, 0, 1);
	glClear(GL_COLOR_BUFFER_BIT);
	eglSwapBuffers(w->egl, w->surface);
	*out = w;
	return RS_OK;
}

void rs_window_destroy(struct rs_window **window)
{
	if (!window || !*window)
		return;
	struct rs_window *w = *window;
	if (w->egl != EGL_NO_DISPLAY && w->egl) {
		if (w->ctx) {
			glDeleteTextures(1, &w->texture);
			glDeleteVertexArrays(1, &w->vao);
			glDeleteProgram(w->program);
		}
		eglMakeCurrent(w->egl, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
		if (w->ctx)
			eglDestroyContext(w->egl, w->ctx);
		if (w->surface)
			eglDestroySurface(w->egl, w->surface);
		eglTerminate(w->egl);
	}
	if (w->dpy) {
		if (w->font)
			XFreeFont(w->dpy, w->font);
		if (w->gc)
			XFreeGC(w->dpy, w->gc);
		if (w->top)
			XDestroyWindow(w->dpy, w->top); /* and its child */
		XCloseDisplay(w->dpy);
	}
	free(w);
	*window = NULL;
}

static enum rs_status draw(struct rs_window *w, struct rs_error *err)
{
	glUseProgram(w->program);
	glActiveTexture(GL_TEXTURE0);
	glBindTexture(GL_TEXTURE_2D, w->texture);
	glUniform1i(glGetUniformLocation(w->program, "image"), 0);
	glBindVertexArray(w->vao);
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	if (glGetError() != GL_NO_ERROR || !eglSwapBuffers(w->egl, w->surface))
		return rs_error_set(err, RS_ERR_DEVICE, "window: drawing the frame failed");
	return RS_OK;
}

enum rs_status rs_window_present(struct rs_window *w, const uint8_t *rgba, uint32_t width,
                                 uint32_t height, struct rs_error *err)
{
	RS_ASSERT(w && rgba);
	if (width != w->width || height != w->height)
		return rs_error_set(err, RS_ERR_INVALID, "window: frame %ux%u in a %ux%u window",
		                    width, height, w->width, w->height);
	glBindTexture(GL_TEXTURE_2D, w->texture);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)width, (GLsizei)height, GL_RGBA,
	                GL_UNSIGNED_BYTE, rgba);
	w->have_frame = 1;
	return draw(w, err);
}

static void draw_status(struct rs_window *w)
{
	XClearArea(w->dpy, w->top, 0, (int)w->height, w->width, STATUS_STRIP, False);
	if (w->font && w->status[0])
		XDrawString(w->dpy, w->top, w->gc, 4, (int)w->height + STATUS_STRIP - 5, w->status,
		            (int)strlen(w->status));
	XFlush(w->dpy);
}

void rs_window_set_title(struct rs_window *w, const char *title)
{
	RS_ASSERT(w && title);
	XStoreName(w->dpy, w->top, title);
	snprintf(w->status, sizeof w->status, "%s", title);
	draw_status(w);
}

enum rs_window_event rs_window_poll(struct rs_window *w)
{
	RS_ASSERT(w);
	enum rs_window_event ev = RS_WINDOW_NONE;
	while (ev == RS_WINDOW_NONE && XPending(w->dpy) > 0) {
		XEvent e;
		XNextEvent(w->dpy, &e);
		if (e.type == Expose && e.xexpose.window == w->win && w->have_frame)
			draw(w, NULL);
		else if (e.type == Expose && e.xexpose.window == w->top)
			draw_status(w);
		else if (e.type == ClientMessage && (Atom)e.xclient.data.l[0] == w->wm_delete)
			ev = RS_WINDOW_QUIT;
		else if (e.type == KeyPress) {
			KeySym k = XLookupKeysym(&e.xkey, 0);
			if (k == XK_q || k == XK_Escape)
				ev = RS_WINDOW_QUIT;
			else if (k == XK_space || k == XK_m)
				ev = RS_WINDOW_SWITCH;
			else if (k == XK_r)
				ev = RS_WINDOW_RECENTRE;
		}
	}
	return ev;
}
