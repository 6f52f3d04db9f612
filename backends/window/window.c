/* The window's X11 side: an image area (the GL child window, exactly the frame's size)
 * over a status strip of its own, so the status never covers the image; keys become
 * events. The GL side (context, display, renderer provider) is window_gl.c. */
#include <X11/Xutil.h>
#include <X11/keysym.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "window_internal.h"

/* The status strip under the image (X core font): two lines, so a 256-pixel window shows
 * the whole status line (split at a " | " that fits, else cut). */
#define STATUS_LINE 14
#define STATUS_STRIP (2 * STATUS_LINE + 4)

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
	enum rs_status st = rs_window_gl_create(w, err);
	if (st != RS_OK) {
		rs_window_destroy(&w);
		return st;
	}
	*out = w;
	return RS_OK;
}

void rs_window_destroy(struct rs_window **window)
{
	if (!window || !*window)
		return;
	struct rs_window *w = *window;
	rs_window_gl_destroy(w);
	if (w->dpy) {
		if (w->font)
			XFreeFont(w->dpy, w->font);
		if (w->gc)
			XFreeGC(w->dpy, w->gc);
		if (w->top)
			XDestroyWindow(w->dpy, w->top); /* and its child */
		XCloseDisplay(w->dpy);
	}
	free(w->last);
	free(w);
	*window = NULL;
}

/* Line 2 starts after the last " | " that lets line 1 fit the width. */
static void draw_status(struct rs_window *w)
{
	XClearArea(w->dpy, w->top, 0, (int)w->height, w->width, STATUS_STRIP, False);
	if (!w->font || !w->status[0]) {
		XFlush(w->dpy);
		return;
	}
	const char *t = w->status;
	int n = (int)strlen(t), first = n, max = (int)w->width - 8;
	if (XTextWidth(w->font, t, n) > max) {
		first = 0;
		for (const char *p = strstr(t, " | "); p; p = strstr(p + 1, " | "))
			if (XTextWidth(w->font, t, (int)(p - t)) <= max)
				first = (int)(p - t);
		if (first == 0) /* no separator fits: cut where the width ends */
			while (first < n && XTextWidth(w->font, t, first + 1) <= max)
				++first;
	}
	int base = (int)w->height + STATUS_LINE;
	XDrawString(w->dpy, w->top, w->gc, 4, base - 2, t, first);
	const char *rest = t + first;
	while (*rest == ' ' || *rest == '|')
		++rest;
	XDrawString(w->dpy, w->top, w->gc, 4, base + STATUS_LINE - 2, rest, (int)strlen(rest));
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
		if (e.type == Expose && e.xexpose.window == w->win && w->last)
			rs_window_gl_redraw(w, NULL);
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
