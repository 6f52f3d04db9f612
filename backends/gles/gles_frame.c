/* Running a plan (gles_plan.c): per step, bind what it reads and draw into its targets;
 * then, as steps of their own, the display pass (colour to RGBA8; not after a displayed
 * run, whose last step wrote it) and the readback of colour, depth, triangle ids and
 * counters. Each pass is timed with a glFinish after it
 * (the per-kernel times of the stats; llvmpipe runs passes one by one anyway, a GPU loses
 * a little overlap). */
#include <math.h>
#include <string.h>

#include "gles_internal.h"

/* Rasterized primary hits, first half: the visibility pass rasterizes every triangle into
 * its target (g->hit[1], free until the second pass) with a fetch-free fragment stage, the
 * nearest distance winning through a 32-bit float depth buffer. visibility.glsl then tests
 * each pixel's ray against its triangle once: in the resolve pass (separate and paper
 * chains) or in the fused chain's first pass. (Testing in the raster's own fragment stage,
 * as before, cost a fetch and a triangle test per covering fragment: llvmpipe shades a whole
 * 4x4 block for every tiny triangle, and writing depth from the shader rules out an early
 * depth test.) */
static enum rs_status visibility(const struct gles *g, const struct rs_gles_program *p,
                                 const struct rs_camera *camera, GLuint vis,
                                 struct rs_render_stats *stats, double t0, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	/* Clip planes around the scene's bounding sphere as seen from this eye. */
	double d2 = 0.0;
	for (int a = 0; a < 3; ++a) {
		double e = camera->eye[a] - g->frame.origin[a] - g->frame.bounds_center[a];
		d2 += e * e;
	}
	double far = 1.01 * (sqrt(d2) + g->frame.bounds_radius) + 1e-30;
	rs_gles_uniform_f(gl, p, U_FAR, (GLfloat)far);
	rs_gles_uniform_f(gl, p, U_NEAR, (GLfloat)(far * 1e-6));
	gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g->depth);
	static const GLenum buf0 = GL_COLOR_ATTACHMENT0;
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, vis, 0);
	for (int i = 1; i < 4; ++i)
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i,
		                         GL_TEXTURE_2D, 0, 0);
	gl->DrawBuffers(1, &buf0);
	enum rs_status st = RS_OK;
	if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
		st = rs_error_set(err, RS_ERR_UNSUPPORTED,
		                  "gles: the raster kernel's render targets are not complete");
	if (st == RS_OK) {
		static const GLfloat miss[4] = {1.0e38f, 0.0f, 0.0f, -1.0f};
		gl->ClearBufferfv(GL_COLOR, 0, miss);
		gl->DepthMask(GL_TRUE);
		static const GLfloat one = 1.0f;
		gl->ClearBufferfv(GL_DEPTH, 0, &one);
		gl->Enable(GL_DEPTH_TEST);
		gl->DepthFunc(GL_LESS);
		gl->DrawArrays(GL_TRIANGLES, 0, (GLsizei)(3 * g->accel.packed.triangle_count));
		gl->Disable(GL_DEPTH_TEST);
	}
	gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, 0);
	if (st != RS_OK)
		return st;
	gl->Finish();
	rs_gles_kernel_time(stats, "raster", rs_now_ms() - t0);
	return rs_gles_check(gl, "raster", err);
}

/* Bind what step `s` reads to its program (made current). */
static void bind_inputs(const struct gles *g, const struct rs_gles_plan *plan,
                        const struct rs_gles_step *s, const struct rs_gles_program *p,
                        const struct rs_camera *camera, float near, GLsizei w, GLsizei h)
{
	const struct rs_gl *gl = &g->gl;
	if (s->bind & BIND_SCENE)
		rs_gles_scene_uniforms(g, p);
	if (s->bind & BIND_CAMERA)
		rs_gles_camera_uniforms(g, p, camera, (uint32_t)w, (uint32_t)h);
	if (s->bind & BIND_NEAR)
		rs_gles_uniform_f(gl, p, U_NEAR, near);
	if (s->bind & BIND_ENVMAP)
		rs_gles_envmap_uniforms(g, p, s->pass, s->mapped);
	if (s->bind & BIND_STATE) {
		static const int units[4] = {UNIT_ORIG, UNIT_DIR, UNIT_ACC, UNIT_CNT};
		static const int names[4] = {U_ORIG, U_DIR, U_ACC, U_CNT};
		for (int k = 0; k < (plan->counters ? 4 : 3); ++k)
			rs_gles_bind(gl, p, units[k], names[k], GL_TEXTURE_2D,
			             rs_gles_target(g, s->in[k]));
	}
	if (s->bind & BIND_HIT)
		rs_gles_bind(gl, p, UNIT_HIT, U_HIT, GL_TEXTURE_2D, rs_gles_target(g, s->in[4]));
	if (s->bind & BIND_VIS)
		rs_gles_bind(gl, p, UNIT_HIT, U_VIS, GL_TEXTURE_2D, g->hit[1]);
}

enum rs_status rs_gles_plan_run(struct gles *g, const struct rs_gles_plan *plan,
                                const struct rs_camera *camera, float near, GLsizei w, GLsizei h,
                                bool display, struct rs_render_stats *stats, struct rs_error *err)
{
	RS_ASSERT(!display || rs_gles_plan_displays(plan));
	rs_gles_frame_state(g, w, h);
	enum rs_status st = RS_OK;
	for (uint32_t i = 0; st == RS_OK && i < plan->count; ++i) {
		const struct rs_gles_step *s = &plan->steps[i];
		const struct rs_gles_program *p = &g->prog[s->prog];
		double t0 = rs_now_ms();
		g->gl.UseProgram(p->id);
		bind_inputs(g, plan, s, p, camera, near, w, h);
		bool shown = display && s->display;
		rs_gles_uniform_i(&g->gl, p, U_DISPLAY, shown ? 1 : 0);
		if (s->raster) {
			st = visibility(g, p, camera, rs_gles_target(g, s->out[0]), stats, t0, err);
			continue;
		}
		GLuint out[4];
		for (int k = 0; k < s->n_out; ++k)
			out[k] = rs_gles_target(g, shown ? s->shown[k] : s->out[k]);
		st = p->compute
		         ? rs_gles_dispatch(g, p, s->name, out, s->n_out, w, h, stats, t0, err)
		         : rs_gles_draw(g, s->name, out, s->n_out, stats, t0, err);
	}
	return st;
}

enum rs_status rs_gles_display(struct gles *g, const struct rs_gles_plan *plan,
                               struct rs_render_stats *stats, struct rs_error *err)
{
	const struct rs_gles_program *p = &g->prog[PROG_DISPLAY];
	double t0 = rs_now_ms();
	g->gl.UseProgram(p->id);
	rs_gles_bind(&g->gl, p, UNIT_ACC, U_ACC, GL_TEXTURE_2D,
	             rs_gles_target(g, plan->result_acc));
	return rs_gles_draw(g, "display", &g->color, 1, stats, t0, err);
}

/* Read a float target (attached as colour 0) into g->scratch. */
static void read_floats(struct gles *g, GLuint tex)
{
	const struct rs_gl *gl = &g->gl;
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
	gl->ReadBuffer(GL_COLOR_ATTACHMENT0);
	gl->ReadPixels(0, 0, (GLsizei)g->desc.width, (GLsizei)g->desc.height, GL_RGBA, GL_FLOAT,
	               g->scratch);
}

enum rs_status rs_gles_readback(struct gles *g, const struct rs_gles_plan *plan,
                                const struct rs_frame *frame, struct rs_render_stats *stats,
                                struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	size_t n = (size_t)g->desc.width * g->desc.height;
	static const GLenum none[4] = {GL_NONE, GL_NONE, GL_NONE, GL_NONE};
	gl->DrawBuffers(4, none);
	for (int i = 1; i < 4; ++i)
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i,
		                         GL_TEXTURE_2D, 0, 0);
	if (frame->rgba8) {
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
		                         g->color, 0);
		gl->ReadBuffer(GL_COLOR_ATTACHMENT0);
		gl->ReadPixels(0, 0, (GLsizei)g->desc.width, (GLsizei)g->desc.height, GL_RGBA,
		               GL_UNSIGNED_BYTE, frame->rgba8);
	}
	if (frame->rgb) {
		read_floats(g, rs_gles_target(g, plan->result_acc));
		for (size_t i = 0; i < n; ++i)
			for (int c = 0; c < 3; ++c)
				frame->rgb[3 * i + c] = g->scratch[4 * i + c];
	}
	if (frame->depth || frame->triangle) {
		read_floats(g, g->hit[0]);
		const uint32_t *order = g->accel.triangle_order;
		/* two levels: the hit texel names the scene triangle itself */
		bool ids = g->accel.two_level.instance_count > 0;
		uint32_t tris =
		    ids ? g->accel.two_level.scene_triangles : g->accel.packed.triangle_count;
		for (size_t i = 0; i < n; ++i) {
			float slot = g->scratch[4 * i + 3];
			bool hit = slot >= 0.0f && slot < (float)tris;
			if (frame->depth)
				frame->depth[i] = hit ? g->scratch[4 * i] : INFINITY;
			if (frame->triangle)
				frame->triangle[i] = !hit  ? RS_NO_SLOT
				                     : ids ? (uint32_t)slot
				                           : order[(uint32_t)slot];
		}
	}
	if (plan->counters) {
		read_floats(g, rs_gles_target(g, plan->result_cnt));
		uint64_t sum[4] = {0, 0, 0, 0};
		for (size_t i = 0; i < n; ++i)
			for (int c = 0; c < 4; ++c)
				sum[c] += (uint64_t)g->scratch[4 * i + c];
		/* a rasterized primary is no traced segment */
		stats->secondary_rays = sum[0] - (g->desc.primary == RS_PRIMARY_RASTER ? 0 : n);
		stats->shadow_rays = sum[1];
		stats->box_tests = sum[2];
		stats->triangle_tests = sum[3];
		stats->counters_valid = true;
	}
	return rs_gles_check(gl, "reading the frame back", err);
}

bool rs_gles_face_probe(struct gles *g, GLuint cube)
{
	const struct rs_gl *gl = &g->gl;
	gl->BindFramebuffer(GL_FRAMEBUFFER, g->fbo);
	gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, 0);
	for (int i = 0; i < 4; ++i)
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i,
		                         GL_TEXTURE_2D, 0, 0);
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
	                         GL_TEXTURE_CUBE_MAP_POSITIVE_X, cube, 0);
	bool ok = gl->CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
	return ok;
}

/* A blit, not a draw: the colour is the plan's last target already, and the copy converts
 * to half floats and reverses columns in one step (no kernel of its own). Source and face
 * are two attachments of the renderer's own framebuffer (no second framebuffer to make):
 * colour 0 is read, colour 1 drawn. */
enum rs_status rs_gles_to_face(struct gles *g, const struct rs_gles_plan *plan, GLuint cube,
                               int face, GLsizei n, bool mirror, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	static const GLenum bufs[2] = {GL_NONE, GL_COLOR_ATTACHMENT1};
	gl->BindFramebuffer(GL_FRAMEBUFFER, g->fbo);
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
	                         rs_gles_target(g, plan->result_acc), 0);
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1,
	                         GL_TEXTURE_CUBE_MAP_POSITIVE_X + (GLenum)face, cube, 0);
	for (int i = 2; i < 4; ++i)
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i,
		                         GL_TEXTURE_2D, 0, 0);
	gl->ReadBuffer(GL_COLOR_ATTACHMENT0);
	gl->DrawBuffers(2, bufs);
	enum rs_status st = RS_OK;
	if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
		st = rs_error_set(err, RS_ERR_UNSUPPORTED,
		                  "gles: a cube map face is not a complete render target");
	if (st == RS_OK)
		gl->BlitFramebuffer(0, 0, n, n, mirror ? n : 0, 0, mirror ? 0 : n, n,
		                    GL_COLOR_BUFFER_BIT, GL_NEAREST);
	/* the next draw attaches its own targets; the face is not left attached */
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, 0, 0);
	return st == RS_OK ? rs_gles_check(gl, "a cube map face", err) : st;
}

enum rs_status rs_gles_read_face(struct gles *g, const struct rs_gles_plan *plan, GLsizei n,
                                 struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
	                         rs_gles_target(g, plan->result_acc), 0);
	gl->ReadBuffer(GL_COLOR_ATTACHMENT0);
	gl->ReadPixels(0, 0, n, n, GL_RGBA, GL_FLOAT, g->scratch);
	return rs_gles_check(gl, "reading a cube map face back", err);
}
