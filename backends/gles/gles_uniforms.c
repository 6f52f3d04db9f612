/* Kernel inputs through each program's cached uniform locations (gles_program.c looks them
 * up once at link): texture units, the frame description (rs_trace_frame) and the camera
 * basis (rs_trace_view) of lib/trace handed to the kernels in fp32, and the cube maps. */
#include "gles_internal.h"

void rs_gles_bind(const struct rs_gl *gl, const struct rs_gles_program *p, int unit, int u,
                  GLenum target, GLuint tex)
{
	gl->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
	gl->BindTexture(target, tex);
	if (p->loc[u] >= 0)
		gl->Uniform1i(p->loc[u], unit);
}

void rs_gles_uniform_i(const struct rs_gl *gl, const struct rs_gles_program *p, int u, GLint v)
{
	if (p->loc[u] >= 0)
		gl->Uniform1i(p->loc[u], v);
}

void rs_gles_uniform_f(const struct rs_gl *gl, const struct rs_gles_program *p, int u, GLfloat v)
{
	if (p->loc[u] >= 0)
		gl->Uniform1f(p->loc[u], v);
}

void rs_gles_uniform_3fv(const struct rs_gl *gl, const struct rs_gles_program *p, int u, GLsizei n,
                         const GLfloat *v)
{
	if (p->loc[u] >= 0 && n > 0)
		gl->Uniform3fv(p->loc[u], n, v);
}

void rs_gles_light_position(const struct gles *g, uint32_t i, GLfloat out[3])
{
	double p[3];
	rs_trace_frame_light(&g->frame, i, p);
	for (int a = 0; a < 3; ++a)
		out[a] = (GLfloat)p[a];
}

void rs_gles_scene_uniforms(const struct gles *g, const struct rs_gles_program *p)
{
	const struct rs_gl *gl = &g->gl;
	const struct rs_trace_frame *f = &g->frame;
	for (int i = 0; i < 4; ++i)
		rs_gles_bind(gl, p, UNIT_NODES + i, U_NODES + i, g->scene_target, g->scene_tex[i]);
	const struct rs_packed *pk = &g->accel.packed;
	rs_gles_uniform_i(gl, p, U_NODE_COUNT, (GLint)pk->node_count);
	rs_gles_uniform_3fv(gl, p, U_GRID_ORIGIN, 1, pk->node_grid_origin);
	rs_gles_uniform_3fv(gl, p, U_GRID_STEP, 1, pk->node_grid_step);
	rs_gles_uniform_i(gl, p, U_TRI_COUNT, (GLint)pk->triangle_count);
	rs_gles_uniform_i(gl, p, U_MATERIAL_COUNT, (GLint)pk->material_count);
	const struct rs_packed_two_level *two = &g->accel.two_level;
	if (two->instance_count) {
		rs_gles_bind(gl, p, UNIT_INSTANCES, U_INSTANCES, g->scene_target, g->instance_tex);
		rs_gles_uniform_i(gl, p, U_TOP_BASE, (GLint)two->top_node_base);
		rs_gles_uniform_i(gl, p, U_TOP_COUNT, (GLint)two->top_node_count);
		rs_gles_uniform_i(gl, p, U_INSTANCE_COUNT, (GLint)two->instance_count);
		rs_gles_uniform_i(gl, p, U_PROTO_INSTANCES,
		                  (GLint)(two->instance_count - (two->loose ? 1u : 0u)));
	}
	rs_gles_uniform_f(gl, p, U_SPAWN_SCALE, (GLfloat)f->spawn_scale);
	rs_gles_uniform_f(gl, p, U_SPAWN_FLOOR, (GLfloat)f->spawn_floor);
	rs_gles_uniform_f(gl, p, U_AMBIENT, (GLfloat)f->ambient);
	GLfloat pos[RS_GLES_MAX_LIGHTS * 3], color[RS_GLES_MAX_LIGHTS * 3];
	for (uint32_t i = 0; i < f->light_count; ++i) {
		rs_gles_light_position(g, i, &pos[3 * i]);
		for (int c = 0; c < 3; ++c)
			color[3 * i + c] = (GLfloat)f->lights[i].color[c];
	}
	rs_gles_uniform_3fv(gl, p, U_LIGHT_POS, (GLsizei)f->light_count, pos);
	rs_gles_uniform_3fv(gl, p, U_LIGHT_COLOR, (GLsizei)f->light_count, color);
	const struct rs_environment *env = &f->env;
	GLfloat center[3], face[18];
	for (int a = 0; a < 3; ++a)
		center[a] = (GLfloat)env->center[a];
	for (int k = 0; k < 6; ++k)
		for (int c = 0; c < 3; ++c)
			face[3 * k + c] = env->face_color[k][c];
	rs_gles_uniform_3fv(gl, p, U_ENV_CENTER, 1, center);
	rs_gles_uniform_f(gl, p, U_ENV_HALF, (GLfloat)env->half_size);
	rs_gles_uniform_3fv(gl, p, U_ENV_COLOR, 6, face);
	rs_gles_uniform_f(gl, p, U_ENV_GRID, (GLfloat)env->grid);
	rs_gles_uniform_f(gl, p, U_ENV_LINE_WIDTH, env->line_width);
	rs_gles_uniform_f(gl, p, U_ENV_LINE_SCALE, env->line_scale);
	if (g->shadow) {
		rs_gles_bind(gl, p, UNIT_SHADOW, U_SHADOW, GL_TEXTURE_2D_ARRAY, g->shadow);
		rs_gles_uniform_i(gl, p, U_SHADOW_SIZE, (GLint)g->desc.shadow_map_size);
		rs_gles_uniform_i(gl, p, U_SHADOW_FILTER, (GLint)g->desc.shadow_filter);
	}
}

void rs_gles_camera_uniforms(const struct gles *g, const struct rs_gles_program *p,
                             const struct rs_camera *c, uint32_t w, uint32_t h)
{
	const struct rs_gl *gl = &g->gl;
	struct rs_trace_view v;
	rs_trace_view_init(c, g->frame.origin, w, h, &v);
	GLfloat eye[3], fw[3], rt[3], upv[3];
	for (int a = 0; a < 3; ++a) {
		eye[a] = (GLfloat)v.eye[a];
		fw[a] = (GLfloat)v.fwd[a];
		rt[a] = (GLfloat)v.right[a];
		upv[a] = (GLfloat)v.up[a];
	}
	rs_gles_uniform_3fv(gl, p, U_EYE, 1, eye);
	rs_gles_uniform_3fv(gl, p, U_FWD, 1, fw);
	rs_gles_uniform_3fv(gl, p, U_RIGHT, 1, rt);
	rs_gles_uniform_3fv(gl, p, U_UP, 1, upv);
	if (p->loc[U_SIZE] >= 0)
		gl->Uniform2f(p->loc[U_SIZE], (GLfloat)v.width, (GLfloat)v.height);
	rs_gles_uniform_f(gl, p, U_TAN, (GLfloat)v.tan_half_fov);
	if (p->loc[U_SHIFT] >= 0)
		gl->Uniform2f(p->loc[U_SHIFT], (GLfloat)v.shift[0], (GLfloat)v.shift[1]);
	if (p->loc[U_JITTER] >= 0)
		gl->Uniform2f(p->loc[U_JITTER], (GLfloat)v.pixel_offset[0],
		              (GLfloat)v.pixel_offset[1]);
}

void rs_gles_envmap_uniforms(const struct gles *g, const struct rs_gles_program *p, uint32_t pass,
                             bool after)
{
	const struct rs_gl *gl = &g->gl;
	rs_gles_bind(gl, p, UNIT_ENVMAP, U_ENVMAP, GL_TEXTURE_CUBE_MAP, g->envmap);
	rs_gles_uniform_i(gl, p, U_ENVMAP_ON, g->envmap_ready && pass > 0);
	rs_gles_uniform_i(gl, p, U_ENVMAP_AFTER, g->envmap_ready && after);
	if (g->desc.reflections != RS_REFLECT_INTERREFLECT)
		return;
	rs_gles_bind(gl, p, UNIT_OBJECTS, U_OBJECTS, GL_TEXTURE_2D, g->object_tex);
	rs_gles_uniform_i(gl, p, U_OBJMAP_ON, g->objmap_read >= 0);
	/* Unused samplers still need a cube map bound: the first set stands in before any. */
	int set = g->objmap_read >= 0 ? g->objmap_read : 0;
	for (uint32_t o = 0; o < RS_RENDER_MAX_MIRROR_OBJECTS; ++o)
		rs_gles_bind(gl, p, UNIT_OBJMAP + (int)o, U_OBJMAP0 + (int)o, GL_TEXTURE_CUBE_MAP,
		             g->objmap[set][o]);
}
