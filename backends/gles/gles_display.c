/* The display step into a window's default framebuffer (present.glsl): for a renderer on a
 * window context, straight from its float colour state after each frame (no readback, no
 * upload), through still-pose refinement's float running mean (accumulate.glsl, ping-pong
 * between two RGBA32F targets; the camera's sample number says restart or add); for RGBA8 frames
 * (remote, CPU, OSMesa), from an uploaded texture. One kernel for both, so a local and a remote
 * frame of the same camera look alike. The bottom of the stack: it uses only the GL table and the
 * program helper, never the renderer's passes. */
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"

struct rs_gles_display {
	struct rs_gl own; /* loaded here when standalone (rs_gles_display_create) */
	const struct rs_gl *gl;
	GLuint prog, vao, tex;
	/* present.glsl's uniforms, looked up once at compile (the step runs every frame) */
	GLint u_size, u_origin, u_scale;
	uint32_t tex_w, tex_h;
	/* refinement (window contexts only): acc[cur] holds the mean */
	GLuint acc_prog, fbo, acc[2];
	GLint u_weight;
	uint32_t acc_w, acc_h;
	int cur;
};

static enum rs_status make(const struct rs_gl *gl, struct rs_gles_display *d, struct rs_error *err)
{
	/* quantize.glsl: the rounding every display value takes (display.glsl's, fused.glsl's) */
	static const char *const files[2] = {"quantize.glsl", "present.glsl"};
	d->gl = gl;
	enum rs_status st =
	    rs_gles_program_compile(gl, "#version 300 es\n", files, 2, &d->prog, err);
	if (st != RS_OK)
		return st;
	d->u_size = gl->GetUniformLocation(d->prog, "u_size");
	d->u_origin = gl->GetUniformLocation(d->prog, "u_origin");
	d->u_scale = gl->GetUniformLocation(d->prog, "u_scale");
	/* the sampler reads unit 0 for good */
	gl->UseProgram(d->prog);
	gl->Uniform1i(gl->GetUniformLocation(d->prog, "u_image"), 0);
	gl->GenVertexArrays(1, &d->vao);
	return rs_gles_check(gl, "making the display step", err);
}

static void release(struct rs_gles_display *d)
{
	const struct rs_gl *gl = d->gl;
	if (gl && gl->DeleteProgram) {
		if (d->prog)
			gl->DeleteProgram(d->prog);
		if (d->vao)
			gl->DeleteVertexArrays(1, &d->vao);
		if (d->tex)
			gl->DeleteTextures(1, &d->tex);
		if (d->acc_prog)
			gl->DeleteProgram(d->acc_prog);
		if (d->fbo)
			gl->DeleteFramebuffers(1, &d->fbo);
		if (d->acc[0])
			gl->DeleteTextures(2, d->acc);
	}
	free(d);
}

/* Draw texture `tex` (w x h texels used, row 0 = top) into the target's rectangle. */
static enum rs_status draw(struct rs_gles_display *d, GLuint tex, uint32_t w, uint32_t h,
                           const struct rs_gles_display_target *t, struct rs_error *err)
{
	const struct rs_gl *gl = d->gl;
	static const GLenum off[] = {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_SCISSOR_TEST,
	                             GL_DITHER}; /* dithering would change the bytes */
	for (size_t i = 0; i < sizeof off / sizeof off[0]; ++i)
		gl->Disable(off[i]);
	gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
	static const GLenum back = GL_BACK;
	gl->DrawBuffers(1, &back);
	gl->Viewport(0, 0, (GLsizei)t->fb_width, (GLsizei)t->fb_height);
	static const GLfloat black[4] = {0.0f, 0.0f, 0.0f, 1.0f};
	gl->ClearBufferfv(GL_COLOR, 0, black);
	/* GL's rows go up: the rectangle's lower-left corner from its top-left one */
	GLint gy = (GLint)t->fb_height - t->y - (GLint)t->height;
	gl->Viewport(t->x, gy, (GLsizei)t->width, (GLsizei)t->height);
	gl->UseProgram(d->prog);
	gl->BindVertexArray(d->vao);
	gl->ActiveTexture(GL_TEXTURE0);
	gl->BindTexture(GL_TEXTURE_2D, tex);
	gl->Uniform2f(d->u_size, (GLfloat)w, (GLfloat)h);
	gl->Uniform2f(d->u_origin, (GLfloat)t->x, (GLfloat)gy);
	/* exactly 1.0 at scale 1, so texel centres land on integers */
	gl->Uniform2f(d->u_scale, (GLfloat)((double)w / t->width),
	              (GLfloat)((double)h / t->height));
	gl->DrawArrays(GL_TRIANGLES, 0, 3);
	return rs_gles_check(gl, "window: drawing the frame", err);
}

enum rs_status rs_gles_display_create(void *(*get_proc_address)(void *ctx, const char *name),
                                      void *ctx, struct rs_gles_display **out, struct rs_error *err)
{
	RS_ASSERT(get_proc_address && out);
	*out = NULL;
	struct rs_gles_display *d = calloc(1, sizeof *d);
	if (!d)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory");
	enum rs_status st = rs_gl_load(&d->own, get_proc_address, ctx, err);
	if (st == RS_OK)
		st = make(&d->own, d, err);
	if (st != RS_OK) {
		release(d);
		return st;
	}
	*out = d;
	return RS_OK;
}

void rs_gles_display_destroy(struct rs_gles_display **display)
{
	if (!display || !*display)
		return;
	release(*display);
	*display = NULL;
}

enum rs_status rs_gles_display_rgba8(struct rs_gles_display *d, const uint8_t *rgba, uint32_t width,
                                     uint32_t height, const struct rs_gles_display_target *to,
                                     struct rs_error *err)
{
	RS_ASSERT(d && rgba && to);
	const struct rs_gl *gl = d->gl;
	if (!width || !height || !to->width || !to->height)
		return rs_error_set(err, RS_ERR_INVALID, "window: an empty frame or rectangle");
	gl->ActiveTexture(GL_TEXTURE0);
	if (!d->tex || d->tex_w != width || d->tex_h != height) {
		if (d->tex)
			gl->DeleteTextures(1, &d->tex);
		gl->GenTextures(1, &d->tex);
		gl->BindTexture(GL_TEXTURE_2D, d->tex);
		gl->TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, (GLsizei)width, (GLsizei)height);
		d->tex_w = width;
		d->tex_h = height;
		enum rs_status st = rs_gles_allocated(gl, "the window's frame texture", GL_RGBA8,
		                                      (GLsizei)width, (GLsizei)height, 1, err);
		if (st != RS_OK)
			return st;
	}
	gl->BindTexture(GL_TEXTURE_2D, d->tex);
	gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
	gl->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)width, (GLsizei)height, GL_RGBA,
	                  GL_UNSIGNED_BYTE, rgba);
	return draw(d, d->tex, width, height, to, err);
}

/* Fold float frame `tex` (w x h) of refinement sample `sample` into the running mean; *out
 * the texture holding the mean after it. */
static enum rs_status accumulate(struct rs_gles_display *d, GLuint tex, uint32_t w, uint32_t h,
                                 uint32_t sample, GLuint *out, struct rs_error *err)
{
	const struct rs_gl *gl = d->gl;
	enum rs_status st = RS_OK;
	if (!d->acc_prog) {
		static const char *const files[1] = {"accumulate.glsl"};
		st = rs_gles_program_compile(gl, "#version 300 es\n", files, 1, &d->acc_prog, err);
		if (st != RS_OK)
			return st;
		d->u_weight = gl->GetUniformLocation(d->acc_prog, "u_weight");
		/* the samplers' units never change */
		gl->UseProgram(d->acc_prog);
		gl->Uniform1i(gl->GetUniformLocation(d->acc_prog, "u_frame"), 0);
		gl->Uniform1i(gl->GetUniformLocation(d->acc_prog, "u_prev"), 1);
		gl->GenFramebuffers(1, &d->fbo);
	}
	if (!d->acc[0] || d->acc_w != w || d->acc_h != h) {
		if (d->acc[0])
			gl->DeleteTextures(2, d->acc);
		gl->GenTextures(2, d->acc);
		for (int i = 0; i < 2; ++i) {
			gl->BindTexture(GL_TEXTURE_2D, d->acc[i]);
			gl->TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, (GLsizei)w, (GLsizei)h);
			/* float textures are not filterable in GLES 3.0: nearest keeps them
			 * complete */
			gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
			gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
		}
		d->acc_w = w;
		d->acc_h = h;
		sample = 0; /* nothing to add to */
		st = rs_gles_allocated(gl, "the refinement targets", GL_RGBA32F, (GLsizei)w,
		                       (GLsizei)h, 2, err);
		if (st != RS_OK)
			return st;
	}
	int next = 1 - d->cur;
	gl->Disable(GL_BLEND);
	gl->Disable(GL_DEPTH_TEST);
	gl->Disable(GL_SCISSOR_TEST);
	gl->BindFramebuffer(GL_FRAMEBUFFER, d->fbo);
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, d->acc[next],
	                         0);
	static const GLenum at0 = GL_COLOR_ATTACHMENT0;
	gl->DrawBuffers(1, &at0);
	if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: the refinement target (RGBA32F) is not renderable");
	gl->Viewport(0, 0, (GLsizei)w, (GLsizei)h);
	gl->UseProgram(d->acc_prog);
	gl->BindVertexArray(d->vao);
	gl->ActiveTexture(GL_TEXTURE0);
	gl->BindTexture(GL_TEXTURE_2D, tex);
	gl->ActiveTexture(GL_TEXTURE1);
	gl->BindTexture(GL_TEXTURE_2D, d->acc[d->cur]);
	gl->Uniform1f(d->u_weight, 1.0f / (float)((double)sample + 1.0));
	gl->DrawArrays(GL_TRIANGLES, 0, 3);
	gl->ActiveTexture(GL_TEXTURE0);
	d->cur = next;
	*out = d->acc[next];
	return rs_gles_check(gl, "refinement: accumulating the frame", err);
}

enum rs_status rs_gles_present(struct gles *g, GLuint tex, uint32_t width, uint32_t height,
                               uint32_t sample, struct rs_render_stats *stats, struct rs_error *err)
{
	double t0 = rs_now_ms();
	if (!g->display) {
		g->display = calloc(1, sizeof *g->display);
		if (!g->display)
			return rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory");
		enum rs_status st = make(&g->gl, g->display, err);
		if (st != RS_OK) {
			rs_gles_display_free(g);
			return st;
		}
	}
	GLuint shown = tex;
	enum rs_status st = accumulate(g->display, tex, width, height, sample, &shown, err);
	struct rs_gles_display_target t;
	g->cops->display_target(g->ctx, &t);
	if (st == RS_OK)
		st = draw(g->display, shown, width, height, &t, err);
	if (st == RS_OK && g->cops->swap)
		st = g->cops->swap(g->ctx, err);
	rs_gles_kernel_time(stats, "present", rs_now_ms() - t0);
	return st;
}

void rs_gles_display_free(struct gles *g)
{
	if (g->display)
		release(g->display);
	g->display = NULL;
}
