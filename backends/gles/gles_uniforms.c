/* Kernel inputs: texture units, uniforms, and the frame description (rs_trace_frame) and
 * camera basis (rs_trace_view) of lib/trace handed to the kernels in fp32. */
#include <math.h>
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

void rs_gles_light_position(const struct gles *g, uint32_t i, GLfloat out[3])
{
	double p[3];
	rs_trace_frame_light(&g->frame, i, p);
	for (int a = 0; a < 3; ++a)
		out[a] = (GLfloat)p[a];
}

/* Scene textures and the frame description's constants (rs_trace_frame), in fp32. */
void rs_gles_scene_uniforms(const struct gles *g, GLuint prog)
{
	const struct rs_gl *gl = &g->gl;
	const struct rs_trace_frame *f = &g->frame;
	static const char *const names[4] = {"u_nodes", "u_tris", "u_normals", "u_materials"};
	for (int i = 0; i < 4; ++i)
		rs_gles_bind(gl, prog, UNIT_NODES + i, names[i], g->scene_target, g->scene_tex[i]);
	const struct rs_packed *p = &g->accel.packed;
	rs_gles_uniform_i(gl, prog, "u_node_count", (GLint)p->node_count);
	rs_gles_uniform_3fv(gl, prog, "u_grid_origin", 1, p->node_grid_origin);
	rs_gles_uniform_3fv(gl, prog, "u_grid_step", 1, p->node_grid_step);
	rs_gles_uniform_i(gl, prog, "u_tri_count", (GLint)p->triangle_count);
	rs_gles_uniform_i(gl, prog, "u_material_count", (GLint)p->material_count);
	rs_gles_uniform_f(gl, prog, "u_spawn_scale", (GLfloat)f->spawn_scale);
	rs_gles_uniform_f(gl, prog, "u_spawn_floor", (GLfloat)f->spawn_floor);
	rs_gles_uniform_f(gl, prog, "u_ambient", (GLfloat)f->ambient);
	GLfloat pos[RS_GLES_MAX_LIGHTS * 3], color[RS_GLES_MAX_LIGHTS * 3];
	for (uint32_t i = 0; i < f->light_count; ++i) {
		rs_gles_light_position(g, i, &pos[3 * i]);
		for (int c = 0; c < 3; ++c)
			color[3 * i + c] = (GLfloat)f->lights[i].color[c];
	}
	rs_gles_uniform_3fv(gl, prog, "u_light_pos", (GLsizei)f->light_count, pos);
	rs_gles_uniform_3fv(gl, prog, "u_light_color", (GLsizei)f->light_count, color);
	const struct rs_environment *env = &f->env;
	GLfloat center[3], face[18];
	for (int a = 0; a < 3; ++a)
		center[a] = (GLfloat)env->center[a];
	for (int k = 0; k < 6; ++k)
		for (int c = 0; c < 3; ++c)
			face[3 * k + c] = env->face_color[k][c];
	rs_gles_uniform_3fv(gl, prog, "u_env_center", 1, center);
	rs_gles_uniform_f(gl, prog, "u_env_half", (GLfloat)env->half_size);
	rs_gles_uniform_3fv(gl, prog, "u_env_color", 6, face);
	rs_gles_uniform_f(gl, prog, "u_env_grid", (GLfloat)env->grid);
	rs_gles_uniform_f(gl, prog, "u_env_line_width", env->line_width);
	rs_gles_uniform_f(gl, prog, "u_env_line_scale", env->line_scale);
	if (g->shadow) {
		rs_gles_bind(gl, prog, UNIT_SHADOW, "u_shadow", GL_TEXTURE_2D_ARRAY, g->shadow);
		rs_gles_uniform_i(gl, prog, "u_shadow_size", (GLint)g->desc.shadow_map_size);
		rs_gles_uniform_i(gl, prog, "u_shadow_filter", (GLint)g->desc.shadow_filter);
	}
}

/* The camera basis lib/trace builds (rs_trace_view: eye in the packed frame, R1), in fp32. */
void rs_gles_camera_uniforms(const struct gles *g, GLuint prog, const struct rs_camera *c)
{
	const struct rs_gl *gl = &g->gl;
	struct rs_trace_view v;
	rs_trace_view_init(c, g->frame.origin, g->desc.width, g->desc.height, &v);
	GLfloat eye[3], fw[3], rt[3], upv[3];
	for (int a = 0; a < 3; ++a) {
		eye[a] = (GLfloat)v.eye[a];
		fw[a] = (GLfloat)v.fwd[a];
		rt[a] = (GLfloat)v.right[a];
		upv[a] = (GLfloat)v.up[a];
	}
	rs_gles_uniform_3fv(gl, prog, "u_eye", 1, eye);
	rs_gles_uniform_3fv(gl, prog, "u_fwd", 1, fw);
	rs_gles_uniform_3fv(gl, prog, "u_right", 1, rt);
	rs_gles_uniform_3fv(gl, prog, "u_up", 1, upv);
	GLint loc = gl->GetUniformLocation(prog, "u_size");
	gl->Uniform2f(loc, (GLfloat)v.width, (GLfloat)v.height);
	rs_gles_uniform_f(gl, prog, "u_tan", (GLfloat)v.tan_half_fov);
	loc = gl->GetUniformLocation(prog, "u_shift");
	if (loc >= 0)
		gl->Uniform2f(loc, (GLfloat)v.shift[0], (GLfloat)v.shift[1]);
}
