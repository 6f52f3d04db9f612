/* One frame of the kernel chain: ray generation, then per pass either intersect + shade
 * (the separate chain) or one fused kernel, then display; ping-pong float targets hold the
 * per-pixel state; readback of colour, depth and counters. Each pass is timed with a
 * glFinish after it (the per-kernel times of the stats; llvmpipe runs passes one by one
 * anyway, a GPU loses a little overlap). */
#include <math.h>
#include <string.h>
#include <time.h>

#include "gles_internal.h"

double rs_gles_now_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void rs_gles_bind(const struct rs_gl *gl, GLuint prog, int unit, const char *name, GLenum target,
                  GLuint tex)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	gl->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
	gl->BindTexture(target, tex);
	if (loc >= 0)
		gl->Uniform1i(loc, unit);
}

static void bind_unit(const struct rs_gl *gl, GLuint prog, int unit, const char *name, GLuint tex)
{
	rs_gles_bind(gl, prog, unit, name, GL_TEXTURE_2D, tex);
}

static void uniform_i(const struct rs_gl *gl, GLuint prog, const char *name, GLint v)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	if (loc >= 0)
		gl->Uniform1i(loc, v);
}

static void uniform_f(const struct rs_gl *gl, GLuint prog, const char *name, GLfloat v)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	if (loc >= 0)
		gl->Uniform1f(loc, v);
}

static void uniform_3fv(const struct rs_gl *gl, GLuint prog, const char *name, GLsizei n,
                        const GLfloat *v)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	if (loc >= 0 && n > 0)
		gl->Uniform3fv(loc, n, v);
}

/* Scene textures and constants shared by the tracing kernels. */
static void scene_uniforms(const struct gles *g, GLuint prog)
{
	const struct rs_gl *gl = &g->gl;
	static const char *const names[4] = {"u_nodes", "u_tris", "u_normals", "u_materials"};
	for (int i = 0; i < 4; ++i)
		bind_unit(gl, prog, UNIT_NODES + i, names[i], g->scene_tex[i]);
	const struct rs_packed *p = &g->accel.packed;
	uniform_i(gl, prog, "u_node_count", (GLint)p->node_count);
	uniform_i(gl, prog, "u_tri_count", (GLint)p->triangle_count);
	uniform_i(gl, prog, "u_material_count", (GLint)p->material_count);
	uniform_f(gl, prog, "u_spawn_scale", g->spawn_scale);
	uniform_f(gl, prog, "u_ambient", g->ambient);
	uniform_3fv(gl, prog, "u_light_pos", (GLsizei)g->light_count, g->light_pos);
	uniform_3fv(gl, prog, "u_light_color", (GLsizei)g->light_count, g->light_color);
	uniform_3fv(gl, prog, "u_env_center", 1, g->env_center);
	uniform_f(gl, prog, "u_env_half", g->env_half);
	uniform_3fv(gl, prog, "u_env_color", 6, g->env_color);
	uniform_f(gl, prog, "u_env_grid", g->env_grid);
	uniform_f(gl, prog, "u_env_line_width", g->env_line_width);
	uniform_f(gl, prog, "u_env_line_scale", g->env_line_scale);
	if (g->shadow) {
		rs_gles_bind(gl, prog, UNIT_SHADOW, "u_shadow", GL_TEXTURE_2D_ARRAY, g->shadow);
		uniform_i(gl, prog, "u_shadow_size", (GLint)g->desc.shadow_map_size);
		uniform_i(gl, prog, "u_shadow_filter", (GLint)g->desc.shadow_filter);
	}
}

/* The camera basis in double, as lib/trace/camera_rays.c builds it, handed over in fp32. */
static void camera_uniforms(const struct gles *g, GLuint prog, const struct rs_camera *c)
{
	const struct rs_gl *gl = &g->gl;
	double f[3], r[3], u[3];
	for (int a = 0; a < 3; ++a)
		f[a] = c->target[a] - c->eye[a];
	double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
	for (int a = 0; a < 3; ++a)
		f[a] = fl > 0.0 ? f[a] / fl : (a == 2 ? -1.0 : 0.0);
	const double *up = c->up;
	r[0] = f[1] * up[2] - f[2] * up[1];
	r[1] = f[2] * up[0] - f[0] * up[2];
	r[2] = f[0] * up[1] - f[1] * up[0];
	double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
	if (!(rl > 1e-300)) {
		double alt[3] = {fabs(f[1]) < 0.9 ? 0.0 : 1.0, fabs(f[1]) < 0.9 ? 1.0 : 0.0, 0.0};
		r[0] = f[1] * alt[2] - f[2] * alt[1];
		r[1] = f[2] * alt[0] - f[0] * alt[2];
		r[2] = f[0] * alt[1] - f[1] * alt[0];
		rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
	}
	for (int a = 0; a < 3; ++a)
		r[a] /= rl;
	u[0] = r[1] * f[2] - r[2] * f[1];
	u[1] = r[2] * f[0] - r[0] * f[2];
	u[2] = r[0] * f[1] - r[1] * f[0];
	GLfloat eye[3], fw[3], rt[3], upv[3];
	for (int a = 0; a < 3; ++a) {
		eye[a] = (GLfloat)(c->eye[a] - g->accel.packed.origin[a]); /* R1 */
		fw[a] = (GLfloat)f[a];
		rt[a] = (GLfloat)r[a];
		upv[a] = (GLfloat)u[a];
	}
	uniform_3fv(gl, prog, "u_eye", 1, eye);
	uniform_3fv(gl, prog, "u_fwd", 1, fw);
	uniform_3fv(gl, prog, "u_right", 1, rt);
	uniform_3fv(gl, prog, "u_up", 1, upv);
	GLint loc = gl->GetUniformLocation(prog, "u_size");
	gl->Uniform2f(loc, (GLfloat)g->desc.width, (GLfloat)g->desc.height);
	uniform_f(gl, prog, "u_tan", (GLfloat)tan(c->fov_y_deg * (3.14159265358979323846 / 360.0)));
	loc = gl->GetUniformLocation(prog, "u_shift");
	if (loc >= 0)
		gl->Uniform2f(loc, (GLfloat)c->shift[0], (GLfloat)c->shift[1]);
}

static void kernel_time(struct rs_render_stats *stats, const char *name, double ms);

/* Attach `n` colour targets and draw the fullscreen triangle with `prog`. */
static enum rs_status draw(struct gles *g, const char *name, const GLuint *targets, int n,
                           struct rs_render_stats *stats, double t0, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	static const GLenum bufs[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1,
	                               GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
	for (int i = 0; i < 4; ++i)
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, bufs[i], GL_TEXTURE_2D,
		                         i < n ? targets[i] : 0, 0);
	gl->DrawBuffers(n, bufs);
	if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: the %s kernel's render targets are not complete", name);
	gl->DrawArrays(GL_TRIANGLES, 0, 3);
	gl->Finish();
	kernel_time(stats, name, rs_gles_now_ms() - t0);
#ifndef NDEBUG
	return rs_gles_check(gl, name, err);
#else
	(void)err;
	return RS_OK;
#endif
}

static void kernel_time(struct rs_render_stats *stats, const char *name, double ms)
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

/* Rasterized primary hits into `hit`: triangle slot, barycentrics and t per pixel, the
 * nearest t winning through a 32-bit float depth buffer holding t / far. */
static enum rs_status raster(struct gles *g, const struct rs_camera *camera, GLuint hit,
                             struct rs_render_stats *stats, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	double t0 = rs_gles_now_ms();
	GLuint prog = g->prog[PROG_RASTER];
	gl->UseProgram(prog);
	scene_uniforms(g, prog);
	camera_uniforms(g, prog, camera);
	/* Clip planes around the scene's bounding sphere as seen from this eye. */
	double d2 = 0.0;
	for (int a = 0; a < 3; ++a) {
		double e = camera->eye[a] - g->accel.packed.origin[a] - g->bounds_center[a];
		d2 += e * e;
	}
	double far = 1.01 * (sqrt(d2) + g->bounds_radius) + 1e-30;
	uniform_f(gl, prog, "u_far", (GLfloat)far);
	uniform_f(gl, prog, "u_near", (GLfloat)(far * 1e-6));
	gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g->depth);
	static const GLenum buf0 = GL_COLOR_ATTACHMENT0;
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, hit, 0);
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
	kernel_time(stats, "raster", rs_gles_now_ms() - t0);
	return rs_gles_check(gl, "raster", err);
}

static void state_inputs(const struct gles *g, GLuint prog, int cur, int cc)
{
	const struct rs_gl *gl = &g->gl;
	bind_unit(gl, prog, UNIT_ORIG, "u_orig", g->state[cur][ST_ORIG]);
	bind_unit(gl, prog, UNIT_DIR, "u_dir", g->state[cur][ST_DIR]);
	bind_unit(gl, prog, UNIT_ACC, "u_acc", g->state[cur][ST_ACC]);
	if (g->desc.counters)
		bind_unit(gl, prog, UNIT_CNT, "u_cnt", g->cnt[cc]);
}

/* Every pass of the chain; returns the index of the state pair and counter texture
 * holding the result. */
static enum rs_status passes(struct gles *g, const struct rs_camera *camera,
                             struct rs_render_stats *stats, int *out_cur, int *out_cc,
                             struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	bool counters = g->desc.counters;
	int cur = 0, cc = 0;
	GLuint t[4] = {g->state[0][ST_ORIG], g->state[0][ST_DIR], g->state[0][ST_ACC], g->cnt[0]};
	gl->UseProgram(g->prog[PROG_RAYGEN]);
	camera_uniforms(g, g->prog[PROG_RAYGEN], camera);
	enum rs_status st = draw(g, "raygen", t, counters ? 4 : 3, stats, rs_gles_now_ms(), err);
	bool fused = g->desc.chain == RS_CHAIN_FUSED && !counters;
	for (uint32_t pass = 0; st == RS_OK && pass < g->desc.passes; ++pass) {
		GLuint hit = g->hit[pass == 0 ? 0 : 1];
		int nxt = 1 - cur;
		double t0 = rs_gles_now_ms();
		bool rasterized = pass == 0 && g->desc.primary == RS_PRIMARY_RASTER;
		if (fused && !rasterized) {
			GLuint prog = g->prog[PROG_FUSED];
			gl->UseProgram(prog);
			scene_uniforms(g, prog);
			state_inputs(g, prog, cur, cc);
			GLuint out[4] = {g->state[nxt][ST_ORIG], g->state[nxt][ST_DIR],
			                 g->state[nxt][ST_ACC], hit};
			st = draw(g, "trace", out, 4, stats, t0, err);
			cur = nxt;
			continue;
		}
		GLuint prog = g->prog[PROG_INTERSECT];
		if (rasterized) {
			st = raster(g, camera, hit, stats, err);
		} else {
			gl->UseProgram(prog);
			scene_uniforms(g, prog);
			state_inputs(g, prog, cur, cc);
			GLuint out_i[2] = {hit, g->cnt[1 - cc]};
			st = draw(g, "intersect", out_i, counters ? 2 : 1, stats, t0, err);
			if (counters)
				cc = 1 - cc;
		}
		if (st != RS_OK)
			break;
		prog = g->prog[PROG_SHADE];
		gl->UseProgram(prog);
		scene_uniforms(g, prog);
		state_inputs(g, prog, cur, cc);
		bind_unit(gl, prog, UNIT_HIT, "u_hit", hit);
		GLuint out_s[4] = {g->state[nxt][ST_ORIG], g->state[nxt][ST_DIR],
		                   g->state[nxt][ST_ACC], g->cnt[1 - cc]};
		st = draw(g, "shade", out_s, counters ? 4 : 3, stats, rs_gles_now_ms(), err);
		if (counters)
			cc = 1 - cc;
		cur = nxt;
	}
	*out_cur = cur;
	*out_cc = cc;
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

static enum rs_status readback(struct gles *g, const struct rs_frame *frame, int cur, int cc,
                               struct rs_render_stats *stats, struct rs_error *err)
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
		read_floats(g, g->state[cur][ST_ACC]);
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
		read_floats(g, g->cnt[cc]);
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
	int cur = 0, cc = 0;
	enum rs_status st = passes(g, camera, &stats, &cur, &cc, err);
	if (st == RS_OK) {
		GLuint prog = g->prog[PROG_DISPLAY];
		g->gl.UseProgram(prog);
		bind_unit(&g->gl, prog, UNIT_ACC, "u_acc", g->state[cur][ST_ACC]);
		st = draw(g, "display", &g->color, 1, &stats, rs_gles_now_ms(), err);
	}
	return st;
}

enum rs_status rs_gles_frame(struct gles *g, const struct rs_camera *camera,
                             const struct rs_frame *frame, struct rs_render_stats *stats,
                             struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	frame_state(g, (GLsizei)g->desc.width, (GLsizei)g->desc.height);
	double t0 = rs_gles_now_ms();
	int cur = 0, cc = 0;
	enum rs_status st = passes(g, camera, stats, &cur, &cc, err);
	if (st == RS_OK && frame->rgba8) {
		GLuint prog = g->prog[PROG_DISPLAY];
		gl->UseProgram(prog);
		bind_unit(gl, prog, UNIT_ACC, "u_acc", g->state[cur][ST_ACC]);
		st = draw(g, "display", &g->color, 1, stats, rs_gles_now_ms(), err);
	}
	stats->render_ms = rs_gles_now_ms() - t0;
	stats->pixels = (uint64_t)g->desc.width * g->desc.height;
	stats->primary_rays = stats->pixels;
	if (st != RS_OK)
		return st;
	double t1 = rs_gles_now_ms();
	st = readback(g, frame, cur, cc, stats, err);
	stats->readback_ms = rs_gles_now_ms() - t1;
	return st;
}
