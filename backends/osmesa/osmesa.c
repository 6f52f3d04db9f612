/* An OSMesa context for the GLES renderer. OSMesa needs a colour buffer to make a context
 * current; the renderer draws into its own framebuffers, so a 1x1 buffer serves. */
#include <GL/osmesa.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_gles.h"
#include "raystream/rs_osmesa.h"

struct osmesa_ctx {
	OSMesaContext context;
	unsigned char pixel[4];
};

static void osmesa_destroy(void *p)
{
	struct osmesa_ctx *c = p;
	if (!c)
		return;
	if (c->context) {
		if (OSMesaGetCurrentContext() == c->context)
			OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
		OSMesaDestroyContext(c->context);
	}
	free(c);
}

static enum rs_status osmesa_make_current(void *p, struct rs_error *err)
{
	struct osmesa_ctx *c = p;
	if (!OSMesaMakeCurrent(c->context, c->pixel, GL_UNSIGNED_BYTE, 1, 1))
		return rs_error_set(err, RS_ERR_DEVICE, "osmesa: OSMesaMakeCurrent failed");
	return RS_OK;
}

static void osmesa_release(void *p)
{
	/* Mesa's gallium OSMesa unbinds with a NULL context and buffer (a context destroyed
	 * while current leaks its framebuffer). */
	(void)p;
	OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
}

static void *osmesa_proc(void *p, const char *name)
{
	(void)p;
	void *f;
	OSMESAproc g = OSMesaGetProcAddress(name);
	memcpy(&f, &g, sizeof f);
	return f;
}

static void osmesa_describe(const void *p, char *out, size_t cap)
{
	(void)p;
	snprintf(out, cap, "OSMesa");
}

static const struct rs_gl_context_ops osmesa_ops = {.backend = "osmesa",
                                                    .make_current = osmesa_make_current,
                                                    .release = osmesa_release,
                                                    .get_proc_address = osmesa_proc,
                                                    .describe = osmesa_describe,
                                                    .destroy = osmesa_destroy};

enum rs_status rs_renderer_create_osmesa(const struct rs_render_desc *desc,
                                         struct rs_renderer **out, struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	struct osmesa_ctx *c = calloc(1, sizeof *c);
	if (!c)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "osmesa: out of memory");
	static const int attr[] = {OSMESA_FORMAT,
	                           OSMESA_RGBA,
	                           OSMESA_DEPTH_BITS,
	                           0,
	                           OSMESA_PROFILE,
	                           OSMESA_CORE_PROFILE,
	                           OSMESA_CONTEXT_MAJOR_VERSION,
	                           3,
	                           OSMESA_CONTEXT_MINOR_VERSION,
	                           3,
	                           0};
	c->context = OSMesaCreateContextAttribs(attr, NULL);
	if (!c->context) {
		free(c);
		return rs_error_set(
		    err, RS_ERR_DEVICE,
		    "osmesa: no OpenGL 3.3 core context (OSMesaCreateContextAttribs)");
	}
	return rs_gles_renderer_create(&osmesa_ops, c, desc, out, err);
}
