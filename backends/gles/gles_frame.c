/* One frame of the kernel chain: ray generation, then per pass one fused kernel, or
 * intersect + shade (the separate chain), or intersect and the paper's environment, shading
 * and next-ray kernels (gles_paper.c), then display; ping-pong float targets hold the
 * per-pixel state; readback of colour, depth and counters. Each pass is timed with a
 * glFinish after it (the per-kernel times of the stats; llvmpipe runs passes one by one
 * anyway, a GPU loses a little overlap). */
#include <math.h>
#include <string.h>

#include "gles_internal.h"

enum rs_status rs_gles_draw(struct gles *g, const char *name, const GLuint *targets, int n,
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

/* Rasterized primary hits, first half: the visibility pass rasterizes every triangle into
 * g->hit[1] (free until the second pass) with a fetch-free fragment stage, the nearest
 * distance winning through a 32-bit float depth buffer. visibility.glsl then tests each
 * pixel's ray against its triangle once: in the resolve pass (separate and paper chains) or
 * in the fused chain's first pass. (Testing in the raster's own fragment stage, as before,
 * cost a fetch and a triangle test per covering fragment: llvmpipe shades a whole 4x4 block
 * for every tiny triangle, and writing depth from the shader rules out an early depth
 * test.) */
static enum rs_status visibility(struct gles *g, const struct rs_camera *camera,
                                 struct rs_render_stats *stats, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	double t0 = rs_now_ms();
	GLuint prog = g->prog[PROG_RASTER];
	gl->UseProgram(prog);
	rs_gles_scene_uniforms(g, prog);
	rs_gles_camera_uniforms(g, prog, camera);
	/* Clip planes around the scene's bounding sphere as seen from this eye. */
	double d2 = 0.0;
	for (int a = 0; a < 3; ++a) {
		double e = camera->eye[a] - g->accel.packed.origin[a] - g->bounds_center[a];
		d2 += e * e;
	}
	double far = 1.01 * (sqrt(d2) + g->bounds_radius) + 1e-30;
	rs_gles_uniform_f(gl, prog, "u_far", (GLfloat)far);
	rs_gles_uniform_f(gl, prog, "u_near", (GLfloat)(far * 1e-6));
	GLuint vis = g->hit[1];
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

/* Rasterized primary hits into `hit`: triangle slot, barycentrics and t per pixel. */
static enum rs_status raster(struct gles *g, const struct rs_camera *camera, GLuint hit,
                             struct rs_render_stats *stats, struct rs_error *err)
{
	enum rs_status st = visibility(g, camera, stats, err);
	if (st != RS_OK)
		return st;
	const struct rs_gl *gl = &g->gl;
	GLuint prog = g->prog[PROG_RESOLVE];
	gl->UseProgram(prog);
	rs_gles_scene_uniforms(g, prog);
	rs_gles_camera_uniforms(g, prog, camera);
	rs_gles_bind_2d(gl, prog, UNIT_HIT, "u_vis", g->hit[1]);
	return rs_gles_draw(g, "resolve", &hit, 1, stats, rs_now_ms(), err);
}

void rs_gles_state_inputs(const struct gles *g, GLuint prog, const struct rs_gles_cursor *c)
{
	const struct rs_gl *gl = &g->gl;
	rs_gles_bind_2d(gl, prog, UNIT_ORIG, "u_orig", g->state[c->st[ST_ORIG]][ST_ORIG]);
	rs_gles_bind_2d(gl, prog, UNIT_DIR, "u_dir", g->state[c->st[ST_DIR]][ST_DIR]);
	rs_gles_bind_2d(gl, prog, UNIT_ACC, "u_acc", g->state[c->st[ST_ACC]][ST_ACC]);
	if (g->desc.counters)
		rs_gles_bind_2d(gl, prog, UNIT_CNT, "u_cnt", g->cnt[c->cnt]);
}

/* The shade kernel of the separate chain: environment, shading and next ray in one pass. */
static enum rs_status shade(struct gles *g, uint32_t pass, GLuint hit, struct rs_gles_cursor *c,
                            struct rs_render_stats *stats, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	bool counters = g->desc.counters;
	GLuint prog = g->prog[PROG_SHADE];
	gl->UseProgram(prog);
	rs_gles_scene_uniforms(g, prog);
	if (g->desc.reflections != RS_REFLECT_TRACE)
		rs_gles_envmap_uniforms(g, prog, pass);
	rs_gles_state_inputs(g, prog, c);
	rs_gles_bind_2d(gl, prog, UNIT_HIT, "u_hit", hit);
	GLuint out[4] = {g->state[1 - c->st[ST_ORIG]][ST_ORIG], g->state[1 - c->st[ST_DIR]][ST_DIR],
	                 g->state[1 - c->st[ST_ACC]][ST_ACC], g->cnt[1 - c->cnt]};
	enum rs_status st =
	    rs_gles_draw(g, "shade", out, counters ? 4 : 3, stats, rs_now_ms(), err);
	for (int s = 0; s < ST_COUNT; ++s)
		c->st[s] = 1 - c->st[s];
	if (counters)
		c->cnt = 1 - c->cnt;
	return st;
}

/* Every pass of the chain; *out says which texture of each pair holds the result. */
static enum rs_status passes(struct gles *g, const struct rs_camera *camera,
                             struct rs_render_stats *stats, struct rs_gles_cursor *out,
                             struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	bool counters = g->desc.counters;
	struct rs_gles_cursor c = {{0, 0, 0}, 0};
	/* Environment mapping switches tracing off per pass: the separate chains only. */
	bool envmap = g->desc.reflections != RS_REFLECT_TRACE;
	bool fused = g->desc.chain == RS_CHAIN_FUSED && !counters && !envmap;
	/* The fused chain's first pass makes its own primary rays (rasterized or traced). */
	enum rs_status st = RS_OK;
	if (!fused) {
		GLuint t[4] = {g->state[0][ST_ORIG], g->state[0][ST_DIR], g->state[0][ST_ACC],
		               g->cnt[0]};
		gl->UseProgram(g->prog[PROG_RAYGEN]);
		rs_gles_camera_uniforms(g, g->prog[PROG_RAYGEN], camera);
		rs_gles_uniform_f(gl, g->prog[PROG_RAYGEN], "u_near", g->capture_near);
		st = rs_gles_draw(g, "raygen", t, counters ? 4 : 3, stats, rs_now_ms(), err);
	}
	/* With the env map every path ends in the second pass: later ones would be empty. */
	uint32_t count = envmap && g->desc.passes > 2 ? 2 : g->desc.passes;
	for (uint32_t pass = 0; st == RS_OK && pass < count; ++pass) {
		GLuint hit = g->hit[pass == 0 ? 0 : 1];
		double t0 = rs_now_ms();
		bool rasterized = pass == 0 && g->desc.primary == RS_PRIMARY_RASTER;
		if (fused) {
			if (rasterized)
				st = visibility(g, camera, stats, err);
			if (st != RS_OK)
				break;
			t0 = rs_now_ms();
			GLuint prog = g->prog[pass > 0     ? PROG_FUSED
			                      : rasterized ? PROG_FUSED_RASTER
			                                   : PROG_FUSED_FIRST];
			gl->UseProgram(prog);
			rs_gles_scene_uniforms(g, prog);
			if (pass == 0) {
				rs_gles_camera_uniforms(g, prog, camera);
				rs_gles_uniform_f(gl, prog, "u_near", g->capture_near);
				if (rasterized)
					rs_gles_bind_2d(gl, prog, UNIT_HIT, "u_vis", g->hit[1]);
			} else {
				rs_gles_state_inputs(g, prog, &c);
			}
			GLuint o[4] = {g->state[1 - c.st[ST_ORIG]][ST_ORIG],
			               g->state[1 - c.st[ST_DIR]][ST_DIR],
			               g->state[1 - c.st[ST_ACC]][ST_ACC], hit};
			/* Nothing reads the last pass's rays, nor its hits after pass 0's (the
			 * frame's depth): not stored (3-5 % of a Cow17 2-pass frame, llvmpipe). */
			if (pass + 1 == count) {
				o[0] = o[1] = 0;
				if (pass > 0)
					o[3] = 0;
			}
			st = rs_gles_draw(g, "trace", o, 4, stats, t0, err);
			for (int s = 0; s < ST_COUNT; ++s)
				c.st[s] = 1 - c.st[s];
			continue;
		}
		if (rasterized) {
			st = raster(g, camera, hit, stats, err);
		} else {
			GLuint prog = g->prog[PROG_INTERSECT];
			gl->UseProgram(prog);
			rs_gles_scene_uniforms(g, prog);
			if (envmap)
				rs_gles_envmap_uniforms(g, prog, pass);
			rs_gles_state_inputs(g, prog, &c);
			GLuint out_i[2] = {hit, g->cnt[1 - c.cnt]};
			st = rs_gles_draw(g, "intersect", out_i, counters ? 2 : 1, stats, t0, err);
			if (counters)
				c.cnt = 1 - c.cnt;
		}
		if (st != RS_OK)
			break;
		if (g->desc.chain == RS_CHAIN_PAPER)
			st = rs_gles_paper_segment(g, pass, hit, &c, stats, err);
		else
			st = shade(g, pass, hit, &c, stats, err);
	}
	*out = c;
	return st;
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

static enum rs_status readback(struct gles *g, const struct rs_frame *frame,
                               const struct rs_gles_cursor *cur, struct rs_render_stats *stats,
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
		read_floats(g, g->state[cur->st[ST_ACC]][ST_ACC]);
		for (size_t i = 0; i < n; ++i)
			for (int c = 0; c < 3; ++c)
				frame->rgb[3 * i + c] = g->scratch[4 * i + c];
	}
	if (frame->depth || frame->triangle) {
		read_floats(g, g->hit[0]);
		const uint32_t *order = g->accel.triangle_order;
		uint32_t tris = g->accel.packed.triangle_count;
		for (size_t i = 0; i < n; ++i) {
			float slot = g->scratch[4 * i + 3];
			bool hit = slot >= 0.0f && slot < (float)tris;
			if (frame->depth)
				frame->depth[i] = hit ? g->scratch[4 * i] : INFINITY;
			if (frame->triangle)
				frame->triangle[i] = hit ? order[(uint32_t)slot] : RS_NO_SLOT;
		}
	}
	if (g->desc.counters) {
		read_floats(g, g->cnt[cur->cnt]);
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

static void frame_state(struct gles *g, GLsizei w, GLsizei h)
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

enum rs_status rs_gles_warm_up(struct gles *g, const struct rs_camera *camera, struct rs_error *err)
{
	frame_state(g, 1, 1);
	struct rs_render_stats stats = {0};
	struct rs_gles_cursor c;
	enum rs_status st = passes(g, camera, &stats, &c, err);
	if (st == RS_OK) {
		GLuint prog = g->prog[PROG_DISPLAY];
		g->gl.UseProgram(prog);
		rs_gles_bind_2d(&g->gl, prog, UNIT_ACC, "u_acc", g->state[c.st[ST_ACC]][ST_ACC]);
		st = rs_gles_draw(g, "display", &g->color, 1, &stats, rs_now_ms(), err);
	}
	return st;
}

enum rs_status rs_gles_frame(struct gles *g, const struct rs_camera *camera,
                             const struct rs_frame *frame, struct rs_render_stats *stats,
                             struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	frame_state(g, (GLsizei)g->desc.width, (GLsizei)g->desc.height);
	double t0 = rs_now_ms();
	struct rs_gles_cursor c;
	enum rs_status st = passes(g, camera, stats, &c, err);
	if (st == RS_OK && frame->rgba8) {
		GLuint prog = g->prog[PROG_DISPLAY];
		gl->UseProgram(prog);
		rs_gles_bind_2d(gl, prog, UNIT_ACC, "u_acc", g->state[c.st[ST_ACC]][ST_ACC]);
		st = rs_gles_draw(g, "display", &g->color, 1, stats, rs_now_ms(), err);
	}
	stats->render_ms = rs_now_ms() - t0;
	stats->pixels = (uint64_t)g->desc.width * g->desc.height;
	stats->primary_rays = stats->pixels;
	if (st != RS_OK)
		return st;
	double t1 = rs_now_ms();
	st = readback(g, frame, &c, stats, err);
	stats->readback_ms = rs_now_ms() - t1;
	return st;
}
