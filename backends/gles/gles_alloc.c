/* GPU allocations checked one by one: after each texture or renderbuffer storage (and each
 * framebuffer or vertex array object) glGetError is read, so out of GPU memory is reported
 * as RS_ERR_NO_MEMORY naming what was being allocated and its size, not as a later pass
 * drawing into an incomplete target; and glGetError after any other step (rs_gles_check). */
#include <stdbool.h>
#include <stdio.h>

#include "gles_internal.h"

/* Name and bytes per texel of the internal formats the renderer allocates. */
static const char *format_name(GLenum format, double *bytes)
{
	switch (format) {
	case GL_RGBA32F:
		*bytes = 16.0;
		return "RGBA32F";
	case GL_RGBA32UI:
		*bytes = 16.0;
		return "RGBA32UI";
	case GL_RGBA8:
		*bytes = 4.0;
		return "RGBA8";
	case GL_R32F:
		*bytes = 4.0;
		return "R32F";
	case GL_RGB16F:
		*bytes = 6.0;
		return "RGB16F";
	case GL_RGBA16F:
		*bytes = 8.0;
		return "RGBA16F";
	case GL_DEPTH_COMPONENT32F:
		*bytes = 4.0;
		return "DEPTH32F";
	default:
		*bytes = 0.0;
		return "?";
	}
}

enum rs_status rs_gles_allocated(const struct rs_gl *gl, const char *what, GLenum format, GLsizei w,
                                 GLsizei h, GLsizei layers, struct rs_error *err)
{
	GLenum e = gl->GetError();
	if (e == GL_NO_ERROR)
		return RS_OK;
	while (gl->GetError() != GL_NO_ERROR) {
	}
	char size[64] = "";
	if (format) {
		double bytes;
		const char *name = format_name(format, &bytes);
		double kib = bytes * (double)w * (double)h * (double)layers / 1024.0;
		bool mib = kib >= 1024.0;
		char dims[32];
		if (layers > 1)
			snprintf(dims, sizeof dims, "%dx%dx%d", (int)w, (int)h, (int)layers);
		else
			snprintf(dims, sizeof dims, "%dx%d", (int)w, (int)h);
		snprintf(size, sizeof size, " (%s %s, %.1f %s)", dims, name,
		         mib ? kib / 1024.0 : kib, mib ? "MiB" : "KiB");
	}
	if (e == GL_OUT_OF_MEMORY)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of GPU memory for %s%s", what,
		                    size);
	return rs_error_set(err, RS_ERR_DEVICE, "gles: GL error 0x%04x allocating %s%s",
	                    (unsigned)e, what, size);
}
enum rs_status rs_gles_check(const struct rs_gl *gl, const char *what, struct rs_error *err)
{
	GLenum e = gl->GetError();
	if (e == GL_NO_ERROR)
		return RS_OK;
	while (gl->GetError() != GL_NO_ERROR) {
	}
	if (e == GL_OUT_OF_MEMORY)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of GPU memory (%s)", what);
	return rs_error_set(err, RS_ERR_DEVICE, "gles: GL error 0x%04x after %s", (unsigned)e,
	                    what);
}
