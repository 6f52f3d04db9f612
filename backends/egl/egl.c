/* Headless EGL contexts for the GLES renderer: device, GBM and surfaceless platforms, a
 * GLES 3 context made current without any surface (EGL_KHR_surfaceless_context). */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <fcntl.h>
#include <gbm.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "raystream/rs_egl.h"
#include "raystream/rs_gles.h"

struct egl_ctx {
	EGLDisplay display;
	EGLContext context;
	int drm_fd; /* GBM: the render node, else -1 */
	struct gbm_device *gbm;
	char platform[16];
};

/* Displays are never terminated: an EGLDisplay is per process and shared by every user of
 * the same platform and device (the host application included), so eglTerminate here
 * would pull the display from under them. eglInitialize on an initialised display is a
 * no-op, so each renderer initialises it and leaves it so. */

static void egl_destroy(void *p)
{
	struct egl_ctx *c = p;
	if (!c)
		return;
	if (c->display != EGL_NO_DISPLAY) {
		eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
		if (c->context != EGL_NO_CONTEXT)
			eglDestroyContext(c->display, c->context);
	}
	if (c->gbm)
		gbm_device_destroy(c->gbm);
	if (c->drm_fd >= 0)
		close(c->drm_fd);
	free(c);
}

static enum rs_status egl_make_current(void *p, struct rs_error *err)
{
	struct egl_ctx *c = p;
	if (!eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, c->context))
		return rs_error_set(err, RS_ERR_DEVICE, "egl: eglMakeCurrent failed (0x%04x)",
		                    (unsigned)eglGetError());
	return RS_OK;
}

static void egl_release(void *p)
{
	struct egl_ctx *c = p;
	eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

static void *egl_proc(void *p, const char *name)
{
	(void)p;
	void *f;
	__eglMustCastToProperFunctionPointerType g = eglGetProcAddress(name);
	memcpy(&f, &g, sizeof f);
	return f;
}

static void egl_describe(const void *p, char *out, size_t cap)
{
	const struct egl_ctx *c = p;
	snprintf(out, cap, "EGL %s", c->platform);
}

static const struct rs_gl_context_ops egl_ops = {.backend = "egl",
                                                 .make_current = egl_make_current,
                                                 .release = egl_release,
                                                 .get_proc_address = egl_proc,
                                                 .describe = egl_describe,
                                                 .destroy = egl_destroy};

/* A GLES 3 context on an initialised display, current without a surface. */
static bool make_context(struct egl_ctx *c)
{
	if (!eglBindAPI(EGL_OPENGL_ES_API))
		return false;
	static const EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_SURFACE_TYPE,
	                                  EGL_PBUFFER_BIT, EGL_NONE};
	EGLConfig cfg = NULL;
	EGLint n = 0;
	if (!eglChooseConfig(c->display, cfg_attr, &cfg, 1, &n) || n < 1) {
		/* No pbuffer configs (some surfaceless drivers): a context needs no config
		 * where EGL_KHR_no_config_context exists. */
		const char *ext = eglQueryString(c->display, EGL_EXTENSIONS);
		if (!ext || !strstr(ext, "EGL_KHR_no_config_context"))
			return false;
		cfg = EGL_NO_CONFIG_KHR;
	}
	static const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
	c->context = eglCreateContext(c->display, cfg, EGL_NO_CONTEXT, ctx_attr);
	if (c->context == EGL_NO_CONTEXT)
		return false;
	if (!eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, c->context)) {
		eglDestroyContext(c->display, c->context);
		c->context = EGL_NO_CONTEXT;
		return false;
	}
	eglMakeCurrent(c->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
	return true;
}

static bool try_display(struct egl_ctx *c, EGLDisplay d)
{
	if (d == EGL_NO_DISPLAY || !eglInitialize(d, NULL, NULL))
		return false;
	c->display = d;
	if (make_context(c))
		return true;
	c->display = EGL_NO_DISPLAY;
	return false;
}

static bool open_device(struct egl_ctx *c)
{
	PFNEGLQUERYDEVICESEXTPROC query;
	__eglMustCastToProperFunctionPointerType f = eglGetProcAddress("eglQueryDevicesEXT");
	memcpy(&query, &f, sizeof query);
	EGLDeviceEXT devices[8];
	EGLint n = 0;
	if (!query || !query(8, devices, &n))
		return false;
	for (EGLint i = 0; i < n; ++i)
		if (try_display(c,
		                eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL)))
			return true;
	return false;
}

static bool open_gbm(struct egl_ctx *c)
{
	char path[32];
	for (int i = 128; i < 136; ++i) {
		snprintf(path, sizeof path, "/dev/dri/renderD%d", i);
		int fd = open(path, O_RDWR | O_CLOEXEC);
		if (fd < 0)
			continue;
		struct gbm_device *gbm = gbm_create_device(fd);
		if (gbm && try_display(c, eglGetPlatformDisplay(EGL_PLATFORM_GBM_KHR, gbm, NULL))) {
			c->drm_fd = fd;
			c->gbm = gbm;
			return true;
		}
		if (gbm)
			gbm_device_destroy(gbm);
		close(fd);
	}
	return false;
}

static bool open_surfaceless(struct egl_ctx *c)
{
	return try_display(
	    c, eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL));
}

static const struct {
	const char *name;
	bool (*open)(struct egl_ctx *c);
} platforms[] = {{"device", open_device}, {"gbm", open_gbm}, {"surfaceless", open_surfaceless}};

enum rs_status rs_renderer_create_egl(const struct rs_render_desc *desc, struct rs_renderer **out,
                                      struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	const char *want =
	    desc && desc->egl_platform ? desc->egl_platform : getenv("RS_EGL_PLATFORM");
	if (want && !*want)
		want = NULL;
	size_t count = sizeof platforms / sizeof platforms[0];
	bool known = !want;
	for (size_t i = 0; want && i < count; ++i)
		known = known || strcmp(want, platforms[i].name) == 0;
	if (!known)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "egl: unknown platform '%s' (device, gbm or surfaceless)",
		                    want);
	struct egl_ctx *c = calloc(1, sizeof *c);
	if (!c)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "egl: out of memory");
	c->display = EGL_NO_DISPLAY;
	c->context = EGL_NO_CONTEXT;
	c->drm_fd = -1;
	for (size_t i = 0; i < count; ++i) {
		if (want && strcmp(want, platforms[i].name) != 0)
			continue;
		if (platforms[i].open(c)) {
			snprintf(c->platform, sizeof c->platform, "%s", platforms[i].name);
			return rs_gles_renderer_create(&egl_ops, c, desc, out, err);
		}
	}
	EGLint e = eglGetError();
	egl_destroy(c);
	char why[48] = "";
	if (e != EGL_SUCCESS)
		snprintf(why, sizeof why, " (EGL error 0x%04x)", (unsigned)e);
	return rs_error_set(err, RS_ERR_DEVICE,
	                    "egl: no EGL display with a GLES 3 context on platform %s%s",
	                    want ? want : "device, gbm or surfaceless", why);
}
