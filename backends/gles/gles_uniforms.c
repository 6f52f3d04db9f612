/* Kernel inputs: texture units, uniforms, the scene constants every tracing kernel reads
 * and the camera basis (built in double, as lib/trace/camera_rays.c builds it). */
#include <math.h>

#include "gles_internal.h"

void rs_gles_bind(const struct rs_gl *gl, GLuint prog, int unit, const char *name, GLenum target,
                  GLuint tex)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	gl->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
	gl->BindTexture(target, tex);
	if (loc >= 0)
		gl->Uniform1i(loc, unit);
}

void rs_gles_bind_2d(const struct rs_gl *gl, GLuint prog, int unit, const char *name, GLuint tex)
{
	rs_gles_bind(gl, prog, unit, name, GL_TEXTURE_2D, tex);
}

void rs_gles_uniform_i(const struct rs_gl *gl, GLuint prog, const char *name, GLint v)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	if (loc >= 0)
		gl->Uniform1i(loc, v);
}

void rs_gles_uniform_f(const struct rs_gl *gl, GLuint prog, const char *name, GLfloat v)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	if (loc >= 0)
		gl->Uniform1f(loc, v);
}

void rs_gles_uniform_3fv(const struct rs_gl *gl, GLuint prog, const char *name, GLsizei n,
                         const GLfloat *v)
{
	GLint loc = gl->GetUniformLocation(prog, name);
	if (loc >= 0 && n > 0)
		gl->Uniform3fv(loc, n, v);
}

/* Scene textures and constants shared by the tracing kernels. */
void rs_gles_scene_uniforms(const struct gles *g, GLuint prog)
{
	const struct rs_gl *gl = &g->gl;
	static const char *const names[4] = {"u_nodes", "u_tris", "u_normals", "u_materials"};
	for (int i = 0; i < 4; ++i)
		rs_gles_bind(gl, prog, UNIT_NODES + i, names[i], g->scene_target, g->scene_tex[i]);
	const struct rs_packed *p = &g->accel.packed;
	rs_gles_uniform_i(gl, prog, "u_node_count", (GLint)p->node_count);
	rs_gles_uniform_3fv(gl, prog, "u_grid_origin", 1, p->node_grid_origin);
	rs_gles_uniform_3fv(gl, prog, "u_grid_step", 1, p->node_grid_step);
	rs_gles_uniform_i(gl, prog, "u_tri_count", (GLint)p->triangle_count);
	rs_gles_uniform_i(gl, prog, "u_material_count", (GLint)p->material_count);
	rs_gles_uniform_f(gl, prog, "u_spawn_scale", g->spawn_scale);
	rs_gles_uniform_f(gl, prog, "u_ambient", g->ambient);
	rs_gles_uniform_3fv(gl, prog, "u_light_pos", (GLsizei)g->light_count, g->light_pos);
	rs_gles_uniform_3fv(gl, prog, "u_light_color", (GLsizei)g->light_count, g->light_color);
	rs_gles_uniform_3fv(gl, prog, "u_env_center", 1, g->env_center);
	rs_gles_uniform_f(gl, prog, "u_env_half", g->env_half);
	rs_gles_uniform_3fv(gl, prog, "u_env_color", 6, g->env_color);
	rs_gles_uniform_f(gl, prog, "u_env_grid", g->env_grid);
	rs_gles_uniform_f(gl, prog, "u_env_line_width", g->env_line_width);
	rs_gles_uniform_f(gl, prog, "u_env_line_scale", g->env_line_scale);
	if (g->shadow) {
		rs_gles_bind(gl, prog, UNIT_SHADOW, "u_shadow", GL_TEXTURE_2D_ARRAY, g->shadow);
		rs_gles_uniform_i(gl, prog, "u_shadow_size", (GLint)g->desc.shadow_map_size);
		rs_gles_uniform_i(gl, prog, "u_shadow_filter", (GLint)g->desc.shadow_filter);
	}
}

/* The camera basis in double, as lib/trace/camera_rays.c builds it, handed over in fp32. */
void rs_gles_camera_uniforms(const struct gles *g, GLuint prog, const struct rs_camera *c)
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
	rs_gles_uniform_3fv(gl, prog, "u_eye", 1, eye);
	rs_gles_uniform_3fv(gl, prog, "u_fwd", 1, fw);
	rs_gles_uniform_3fv(gl, prog, "u_right", 1, rt);
	rs_gles_uniform_3fv(gl, prog, "u_up", 1, upv);
	GLint loc = gl->GetUniformLocation(prog, "u_size");
	gl->Uniform2f(loc, (GLfloat)g->desc.width, (GLfloat)g->desc.height);
	rs_gles_uniform_f(gl, prog, "u_tan", (GLfloat)tan(c->fov_y_deg * (RS_PI / 360.0)));
	loc = gl->GetUniformLocation(prog, "u_shift");
	if (loc >= 0)
		gl->Uniform2f(loc, (GLfloat)c->shift[0], (GLfloat)c->shift[1]);
}
