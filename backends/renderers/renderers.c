/* Backend names to create functions. GL backends are compiled in only when their folder
 * is part of the build (RS_RENDERERS_HAVE_*), so lib/ never depends on a driver. */
#include <string.h>

#include "raystream/rs_renderers.h"

#if RS_RENDERERS_HAVE_EGL
#include "raystream/rs_egl.h"
#endif
#if RS_RENDERERS_HAVE_OSMESA
#include "raystream/rs_osmesa.h"
#endif

struct backend_entry {
	const char *name;
	enum rs_status (*create)(const struct rs_render_desc *desc, struct rs_renderer **out,
	                         struct rs_error *err);
};

static const struct backend_entry backends[] = {
    {"cpu", rs_renderer_create_cpu},
#if RS_RENDERERS_HAVE_EGL
    {"egl", rs_renderer_create_egl},
#endif
#if RS_RENDERERS_HAVE_OSMESA
    {"osmesa", rs_renderer_create_osmesa},
#endif
};

static const char *const known[] = {"cpu", "egl", "osmesa"};

static const struct backend_entry *find(const char *name)
{
	for (size_t i = 0; i < sizeof backends / sizeof backends[0]; ++i)
		if (strcmp(backends[i].name, name) == 0)
			return &backends[i];
	return NULL;
}

/* Append `text` to the string in buf (cap bytes), truncating. */
static void append(char *buf, size_t cap, const char *text)
{
	size_t used = strlen(buf), n = strlen(text);
	if (n > cap - 1 - used)
		n = cap - 1 - used;
	memcpy(buf + used, text, n);
	buf[used + n] = '\0';
}

/* "auto": the GL backends in table order (egl, then osmesa), then cpu. Only a failure to
 * get a context (RS_ERR_DEVICE, RS_ERR_UNSUPPORTED) moves on: a descriptor the GL backend
 * refuses is refused, not quietly rendered elsewhere. */
static enum rs_status open_auto(const struct rs_render_desc *desc, struct rs_renderer **out,
                                struct rs_error *note, struct rs_error *err)
{
	size_t count = sizeof backends / sizeof backends[0];
	char why[RS_ERROR_MESSAGE_MAX] = "";
	for (size_t i = 1; i < count; ++i) {
		struct rs_error gl_err = {0};
		enum rs_status st = backends[i].create(desc, out, &gl_err);
		if (st == RS_OK)
			return RS_OK;
		if (st != RS_ERR_DEVICE && st != RS_ERR_UNSUPPORTED) {
			if (err)
				*err = gl_err;
			return st;
		}
		append(why, sizeof why, why[0] ? "; " : "");
		append(why, sizeof why, gl_err.message);
	}
	if (count == 1)
		rs_error_set(note, RS_OK, "auto: this build has no GL backend; rendering on cpu");
	else
		rs_error_set(note, RS_OK, "auto: no GL context opened (%s); rendering on cpu", why);
	return rs_renderer_create_cpu(desc, out, err);
}

enum rs_status rs_renderer_open(const char *backend, const struct rs_render_desc *desc,
                                struct rs_renderer **out, struct rs_error *err)
{
	return rs_renderer_open_noted(backend, desc, out, NULL, err);
}

enum rs_status rs_renderer_open_noted(const char *backend, const struct rs_render_desc *desc,
                                      struct rs_renderer **out, struct rs_error *out_note,
                                      struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	rs_error_clear(out_note);
	if (!backend || !*backend)
		backend = desc && desc->backend && *desc->backend ? desc->backend : "auto";
	if (strcmp(backend, "auto") == 0)
		return open_auto(desc, out, out_note, err);
	const struct backend_entry *entry = find(backend);
	if (entry)
		return entry->create(desc, out, err);
	for (size_t i = 0; i < sizeof known / sizeof known[0]; ++i)
		if (strcmp(known[i], backend) == 0)
			return rs_error_set(
			    err, RS_ERR_UNSUPPORTED,
			    "render backend '%s' is not part of this build (have: %s)", backend,
			    rs_renderer_backends());
	return rs_error_set(err, RS_ERR_INVALID, "unknown render backend '%s' (have: %s)", backend,
	                    rs_renderer_backends());
}

bool rs_renderer_has_backend(const char *name)
{
	return name && (strcmp(name, "auto") == 0 || find(name) != NULL);
}

const char *rs_renderer_backends(void)
{
	return "cpu"
#if RS_RENDERERS_HAVE_EGL
	       ",egl"
#endif
#if RS_RENDERERS_HAVE_OSMESA
	       ",osmesa"
#endif
	    ;
}
