/* Leaf helpers for every draw: the renderer's GL state for a viewport, a fullscreen pass into
 * colour targets, or a compute dispatch into the same textures as images, with its timing. */
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

/* A pass's end: finish, its time since t0 to kernel `name`; GL errors checked in debug
 * builds (a release build leaves that to the frame's readback). */
static enum rs_status finish(const struct rs_gl *gl, const char *name,
                             struct rs_render_stats *stats, double t0, struct rs_error *err)
{
	gl->Finish();
	rs_gles_kernel_time(stats, name, rs_now_ms() - t0);
#ifndef NDEBUG
	return rs_gles_check(gl, name, err);
#else
	(void)err;
	return RS_OK;
#endif
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
	return finish(gl, name, stats, t0, err);
}

/* The compute kernel's work group is 8x8 pixels (fused.glsl's local_size). */
#define GROUP_SIDE 8

enum rs_status rs_gles_dispatch(const struct gles *g, const struct rs_gles_program *p,
                                const char *name, const GLuint *targets, int n, GLsizei w,
                                GLsizei h, struct rs_render_stats *stats, double t0,
                                struct rs_error *err)
{
	RS_ASSERT(p->compute && n <= 4 && w > 0 && h > 0);
	const struct rs_gl *gl = &g->gl;
	/* A unit whose output is dropped still gets a texture (one the pass stores anyway):
	 * an image uniform over an empty unit is an error on some drivers, not a no-op. */
	GLuint any = 0;
	for (int k = 0; k < n && !any; ++k)
		any = targets[k];
	RS_ASSERT(any);
	GLint stores = 0;
	for (int k = 0; k < 4; ++k) {
		GLuint t = k < n ? targets[k] : 0;
		gl->BindImageTexture((GLuint)k, t ? t : any, 0, GL_FALSE, 0, GL_WRITE_ONLY,
		                     GL_RGBA32F);
		stores |= t ? 1 << k : 0;
	}
	gl->Uniform1i(p->loc[U_STORES], stores);
	gl->Uniform2f(p->loc[U_EXTENT], (GLfloat)w, (GLfloat)h);
	gl->DispatchCompute((GLuint)(w + GROUP_SIDE - 1) / GROUP_SIDE,
	                    (GLuint)(h + GROUP_SIDE - 1) / GROUP_SIDE, 1);
	/* The next pass samples these textures, the readback and the cube-face copy read them
	 * through the framebuffer: image stores are incoherent with all of those until a
	 * barrier. One for all (a pass, not a texel, is the unit here). */
	gl->MemoryBarrier(GL_ALL_BARRIER_BITS);
	return finish(gl, name, stats, t0, err);
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
