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

enum rs_status rs_renderer_open(const char *backend, const struct rs_render_desc *desc,
                                struct rs_renderer **out, struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	if (!backend || !*backend)
		backend = "cpu";
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
	return name && find(name) != NULL;
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
