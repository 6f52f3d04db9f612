/* The viewer's window through backends/window (rs_window.h) when this build has it. */
#include <stdio.h>

#include "viewer.h"

#if defined(RS_VIEWER_HAVE_WINDOW)
#include "raystream/rs_window.h"

int viewer_window_open(struct viewer *v)
{
	struct rs_error err = {0};
	struct rs_window_desc d = {
	    .width = v->o.width, .height = v->o.height, .title = "raystream-viewer"};
	if (rs_window_create(&d, &v->window, &err) != RS_OK) {
		fprintf(stderr, "raystream-viewer: %s (use --headless without a display)\n",
		        err.message);
		return -1;
	}
	return 0;
}

int viewer_window_renderer(struct viewer *v, const struct rs_render_desc *desc,
                           struct rs_renderer **out, struct rs_error *err)
{
	return rs_window_renderer_create(v->window, desc, out, err) == RS_OK ? 0 : -1;
}

void viewer_window_present_image(struct viewer *v, const uint8_t *rgba, uint32_t w, uint32_t h)
{
	struct rs_error err = {0};
	if (rs_window_present(v->window, rgba, w, h, &err) != RS_OK)
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
}

void viewer_window_present(struct viewer *v)
{
	struct rs_error err = {0};
	if (rs_window_present(v->window, v->rgba, v->o.width, v->o.height, &err) != RS_OK)
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
}

void viewer_window_caption(struct viewer *v, const char *text)
{
	rs_window_set_title(v->window, text);
}

enum viewer_key viewer_window_poll(struct viewer *v)
{
	switch (rs_window_poll(v->window)) {
	case RS_WINDOW_QUIT:
		return VIEWER_KEY_QUIT;
	case RS_WINDOW_SWITCH:
		return VIEWER_KEY_SWITCH;
	case RS_WINDOW_RECENTRE:
		return VIEWER_KEY_RECENTRE;
	default:
		return VIEWER_KEY_NONE;
	}
}

void viewer_window_close(struct viewer *v)
{
	rs_window_destroy(&v->window);
}

#else

int viewer_window_renderer(struct viewer *v, const struct rs_render_desc *desc,
                           struct rs_renderer **out, struct rs_error *err)
{
	(void)v;
	(void)desc;
	(void)out;
	rs_error_set(err, RS_ERR_UNSUPPORTED, "this build has no window backend");
	return -1;
}

int viewer_window_open(struct viewer *v)
{
	(void)v;
	fprintf(stderr, "raystream-viewer: this build has no window backend (X11/EGL); use "
	                "--headless\n");
	return -1;
}

void viewer_window_present(struct viewer *v)
{
	(void)v;
}

void viewer_window_caption(struct viewer *v, const char *text)
{
	(void)v;
	(void)text;
}

void viewer_window_present_image(struct viewer *v, const uint8_t *rgba, uint32_t w, uint32_t h)
{
	(void)v;
	(void)rgba;
	(void)w;
	(void)h;
}

enum viewer_key viewer_window_poll(struct viewer *v)
{
	(void)v;
	return VIEWER_KEY_NONE;
}

void viewer_window_close(struct viewer *v)
{
	(void)v;
}
#endif
