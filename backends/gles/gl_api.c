/* Loading the GL entry point table from the context backend's get_proc_address. */
#include <string.h>

#include "gl_api.h"
#include "gles_seams.h"

enum rs_status rs_gl_load(struct rs_gl *gl, void *(*get)(void *ctx, const char *name), void *ctx,
                          struct rs_error *err)
{
	memset(gl, 0, sizeof *gl);
	void *p;
	/* Function pointers are stored through memcpy: ISO C has no object-to-function cast. */
#define RS_GL_LOAD(ret, name, params)                                                              \
	p = get(ctx, "gl" #name);                                                                  \
	if (!p)                                                                                    \
		return rs_error_set(err, RS_ERR_UNSUPPORTED,                                       \
		                    "gles: the GL context has no gl" #name " (GLES 3.0 needed)");  \
	memcpy(&gl->name, &p, sizeof p);
	RS_GL_FUNCS(RS_GL_LOAD)
#undef RS_GL_LOAD
	static const char *const tex_buffer[3] = {"glTexBuffer", "glTexBufferOES",
	                                          "glTexBufferEXT"};
	for (int i = 0; i < 3 && !gl->TexBuffer; ++i)
		if ((p = get(ctx, tex_buffer[i])) != NULL)
			memcpy(&gl->TexBuffer, &p, sizeof p);
	/* GLES 3.1 compute: all three or none */
	void *dispatch = get(ctx, "glDispatchCompute"), *image = get(ctx, "glBindImageTexture"),
	     *barrier = get(ctx, "glMemoryBarrier");
	if (dispatch && image && barrier) {
		memcpy(&gl->DispatchCompute, &dispatch, sizeof dispatch);
		memcpy(&gl->BindImageTexture, &image, sizeof image);
		memcpy(&gl->MemoryBarrier, &barrier, sizeof barrier);
	}
	if (rs__gl_fault_hook) /* test builds only (gles_seams.h) */
		rs__gl_fault_hook(gl);
	return RS_OK;
}
