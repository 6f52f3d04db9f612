/* Leaf helpers for every draw: the renderer's GL state for a viewport, a fullscreen pass into
 * colour targets with its timing. */
#include <string.h>

#include "gles_internal.h"

void rs_gles_frame_state(const struct gles *g, GLsizei w, GLsizei h)
{
	const struct rs_gl *gl = &g->gl;
	static const GLenum off[] = {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_SCISSOR_TEST,
	                             GL_DITHER};
	for (size_t i = 0; i < sizeof off / sizeof off[0]; ++i)
		gl->Disable(off[i]);
	gl->BindVertexArray(g->vao);
	gl->BindFramebuffer(GL_FRAMEBUFFER, g->fbo);
	gl->Viewport(0, 0, w, h);
	gl->PixelStorei(GL_PACK_ALIGNMENT, 4);
}

enum rs_status rs_gles_draw(const struct gles *g, const char *name, const GLuint *targets, int n,
                            struct rs_render_stats *stats, double t0, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	GLenum bufs[4];
	for (int i = 0; i < 4; ++i) {
		GLenum at = GL_COLOR_ATTACHMENT0 + (GLenum)i;
		bufs[i] = i < n && targets[i] ? at : GL_NONE;
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, at, GL_TEXTURE_2D, i < n ? targets[i] : 0,
		                         0);
	}
	gl->DrawBuffers(n, bufs);
	if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: the %s kernel's render targets are not complete", name);
	gl->DrawArrays(GL_TRIANGLES, 0, 3);
	gl->Finish();
	rs_gles_kernel_time(stats, name, rs_now_ms() - t0);
#ifndef NDEBUG
	return rs_gles_check(gl, name, err);
#else
	(void)err;
	return RS_OK;
#endif
}

void rs_gles_kernel_time(struct rs_render_stats *stats, const char *name, double ms)
{
	uint32_t k = 0;
	while (k < stats->kernel_count && strcmp(stats->kernels[k].name, name) != 0)
		++k;
	if (k == stats->kernel_count && k < RS_RENDER_MAX_KERNELS) {
		stats->kernel_count++;
		memset(&stats->kernels[k], 0, sizeof stats->kernels[k]);
		strncpy(stats->kernels[k].name, name, sizeof stats->kernels[k].name - 1);
	}
	if (k < RS_RENDER_MAX_KERNELS) {
		stats->kernels[k].calls++;
		stats->kernels[k].ms += ms;
	}
}
