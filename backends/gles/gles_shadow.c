/* Cube shadow maps for point lights (the paper's alternative to shadow feelers): per light
 * six faces of an R32F array texture holding the distance from the light to the nearest
 * surface, rendered once at set_scene (lights and geometry do not change per frame; the
 * tracked viewer moves only the camera). Looked up with a box filter by surface.glsl. */
#include <math.h>

#include "gles_internal.h"

static enum rs_status face(struct gles *g, const struct rs_gles_program *p, uint32_t light, int f,
                           double far, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	gl->FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, g->shadow, 0,
	                            (GLint)(6 * light + (uint32_t)f));
	if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: the shadow map's render targets are not complete");
	static const GLfloat none[4] = {1.0e38f, 0.0f, 0.0f, 1.0f};
	static const GLfloat one = 1.0f;
	gl->ClearBufferfv(GL_COLOR, 0, none);
	gl->ClearBufferfv(GL_DEPTH, 0, &one);
	rs_gles_uniform_i(gl, p, U_AXIS, f / 2);
	rs_gles_uniform_f(gl, p, U_SIGN, f % 2 ? -1.0f : 1.0f);
	rs_gles_uniform_f(gl, p, U_FAR, (GLfloat)far);
	rs_gles_uniform_f(gl, p, U_NEAR, (GLfloat)(far * 1e-5));
	gl->DrawArrays(GL_TRIANGLES, 0, (GLsizei)(3 * g->accel.packed.triangle_count));
	return RS_OK;
}

enum rs_status rs_gles_shadow_maps(struct gles *g, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	GLsizei size = (GLsizei)g->desc.shadow_map_size;
	uint32_t lights = g->frame.light_count;
	GLsizei layers = (GLsizei)(6 * (lights ? lights : 1));
	gl->GenTextures(1, &g->shadow);
	gl->BindTexture(GL_TEXTURE_2D_ARRAY, g->shadow);
	gl->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
	gl->TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
	gl->TexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_R32F, size, size, layers, 0, GL_RED, GL_FLOAT,
	               NULL);
	enum rs_status st =
	    rs_gles_allocated(gl, "the cube shadow maps", GL_R32F, size, size, layers, err);
	if (st != RS_OK)
		return st;
	gl->GenRenderbuffers(1, &g->shadow_depth);
	gl->BindRenderbuffer(GL_RENDERBUFFER, g->shadow_depth);
	gl->RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, size, size);
	st = rs_gles_allocated(gl, "the shadow maps' depth buffer", GL_DEPTH_COMPONENT32F, size,
	                       size, 1, err);
	if (st != RS_OK || g->accel.packed.triangle_count == 0)
		return st;

	const struct rs_gles_program *p = &g->prog[PROG_SHADOW];
	gl->UseProgram(p->id);
	rs_gles_bind(gl, p, UNIT_TRIS, U_TRIS, g->scene_target, g->scene_tex[UNIT_TRIS]);
	gl->BindVertexArray(g->vao);
	gl->BindFramebuffer(GL_FRAMEBUFFER, g->fbo);
	static const GLenum buf0 = GL_COLOR_ATTACHMENT0;
	for (int i = 1; i < 4; ++i)
		gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i,
		                         GL_TEXTURE_2D, 0, 0);
	gl->DrawBuffers(1, &buf0);
	gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
	                            g->shadow_depth);
	gl->Viewport(0, 0, size, size);
	gl->Disable(GL_CULL_FACE);
	gl->Disable(GL_BLEND);
	gl->Enable(GL_DEPTH_TEST);
	gl->DepthFunc(GL_LESS);
	gl->DepthMask(GL_TRUE);
	const double *bc = g->frame.bounds_center;
	for (uint32_t l = 0; st == RS_OK && l < lights; ++l) {
		float lp[3];
		rs_gles_light_position(g, l, lp);
		rs_gles_uniform_3fv(gl, p, U_LIGHT, 1, lp);
		double d2 = 0.0;
		for (int a = 0; a < 3; ++a)
			d2 += (lp[a] - bc[a]) * (lp[a] - bc[a]);
		double far = 1.01 * (sqrt(d2) + g->frame.bounds_radius) + 1e-30;
		for (int f = 0; st == RS_OK && f < 6; ++f)
			st = face(g, p, l, f, far, err);
	}
	gl->Disable(GL_DEPTH_TEST);
	gl->FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, 0);
	gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
	if (st == RS_OK)
		st = rs_gles_check(gl, "rendering the shadow maps", err);
	return st;
}
