/* Inter-reflection environment mapping (RS_REFLECT_INTERREFLECT, the paper's Table 3 middle
 * column): a cube map per reflective object, captured every frame from the centre of the
 * object's bounding sphere with primary rays that start on that sphere (so the object does
 * not see itself), bounce by bounce: bounce 1 sees the scene traced at 1 pass, bounce k
 * also the objects' maps of bounce k-1 (two sets, ping-pong). A ray leaving a mirror
 * object then reads its own object's map (surface.glsl finds the object by the ray's skip
 * slot through u_objects); rays from other surfaces read the classic map. The two sets
 * are made at set_scene; a bounce renders into one set on the GPU (gles_envmap.c) while its
 * rays read the other. */
#include <math.h>
#include <stdlib.h>

#include "gles_internal.h"

/* Row width of the triangle -> object texture; GLES 3.0 guarantees 2048. */
#define OBJECT_ROW 2048u

enum rs_status rs_gles_interreflect_setup(struct gles *g, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	const struct rs_scene *scene = g->scene;
	size_t tris = rs_scene_triangle_count(scene), count = 0;
	size_t rows = tris ? (tris + OBJECT_ROW - 1) / OBJECT_ROW : 1;
	if (rows > (size_t)g->max_tex)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "gles: %zu triangles need a %ux%zu object texture (limit %d)",
		                    tris, OBJECT_ROW, rows, (int)g->max_tex);
	uint32_t *of = malloc((tris ? tris : 1) * sizeof(uint32_t));
	float *texels = calloc(rows * OBJECT_ROW, sizeof(float));
	enum rs_status st = RS_OK;
	if (!of || !texels)
		st = rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory grouping mirrors");
	if (st == RS_OK) {
		st = rs_scene_reflective_objects(scene, of, g->objects,
		                                 RS_RENDER_MAX_MIRROR_OBJECTS, &count, err);
		if (st == RS_ERR_LIMIT)
			rs_error_set(
			    err, RS_ERR_LIMIT,
			    "gles: inter-reflection maps at most %u mirror objects, the scene "
			    "has %zu",
			    RS_RENDER_MAX_MIRROR_OBJECTS, count);
	}
	for (size_t i = 0; st == RS_OK && i < rows * OBJECT_ROW; ++i)
		texels[i] = i < tris && of[i] != RS_SCENE_NO_OBJECT ? (float)of[i] : -1.0f;
	if (st == RS_OK) {
		g->object_count = (uint32_t)count;
		gl->GenTextures(1, &g->object_tex);
		gl->ActiveTexture(GL_TEXTURE0 + UNIT_OBJECTS);
		gl->BindTexture(GL_TEXTURE_2D, g->object_tex);
		gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
		gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
		gl->TexImage2D(GL_TEXTURE_2D, 0, GL_R32F, (GLsizei)OBJECT_ROW, (GLsizei)rows, 0,
		               GL_RED, GL_FLOAT, texels);
		st = rs_gles_allocated(gl, "the triangle -> mirror object texture", GL_R32F,
		                       (GLsizei)OBJECT_ROW, (GLsizei)rows, 1, err);
		g->objmap_read = -1;
	}
	if (st == RS_OK) {
		/* Every sampler needs a complete cube map bound: 1x1 black for unused slots. */
		static const float black[3] = {0.0f, 0.0f, 0.0f};
		gl->GenTextures(2 * RS_RENDER_MAX_MIRROR_OBJECTS, &g->objmap[0][0]);
		/* Both sets made once: every frame's bounces only render into them. */
		for (int s = 0; s < 2; ++s)
			for (uint32_t o = 0; st == RS_OK && o < count; ++o)
				st = rs_gles_cube_alloc(g, g->objmap[s][o],
				                        "a mirror object's cube map", err);
		for (int s = 0; s < 2; ++s)
			for (uint32_t o = count; st == RS_OK && o < RS_RENDER_MAX_MIRROR_OBJECTS;
			     ++o) {
				gl->BindTexture(GL_TEXTURE_CUBE_MAP, g->objmap[s][o]);
				for (GLenum f = 0; st == RS_OK && f < 6; ++f) {
					gl->TexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0,
					               GL_RGB16F, 1, 1, 0, GL_RGB, GL_FLOAT, black);
					st = rs_gles_allocated(gl, "an unused mirror cube map face",
					                       GL_RGB16F, 1, 1, 1, err);
				}
				gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER,
				                  GL_NEAREST);
				gl->TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER,
				                  GL_NEAREST);
			}
	}
	free(of);
	free(texels);
	return st;
}

enum rs_status rs_gles_interreflect_capture(struct gles *g, struct rs_error *err)
{
	enum rs_status st = RS_OK;
	g->objmap_read = -1;
	for (uint32_t b = 0; st == RS_OK && b < g->desc.reflection_bounces; ++b) {
		int set = (int)(b & 1u);
		for (uint32_t o = 0; st == RS_OK && o < g->object_count; ++o) {
			/* Just outside the sphere through the farthest vertex: the start points lie
			 * beyond every triangle of the object, and rays leaving the centre's sphere
			 * outwards never come back into it. The margin is a share of the radius and
			 * 8 ulps of the centre's float in the packed frame, never a fixed length: a
			 * fixed 1e-6 put the points far outside an object 1e-7 wide (R7). */
			double c = 0.0;
			for (int a = 0; a < 3; ++a)
				c = fmax(c, fabs(g->objects[o].center[a] - g->frame.origin[a]));
			float near = (float)(g->objects[o].radius * (1.0 + 1e-4) + c * 0x1p-20 +
			                     RS_TRACE_SPAWN_FLOOR_MIN);
			const struct rs_gles_plan *plan =
			    &g->plans[b == 0 ? PLAN_BOUNCE_1 : PLAN_BOUNCE_N];
			st = rs_gles_capture_cube(g, plan, g->objects[o].center, near,
			                          g->objmap[set][o], err);
		}
		if (st == RS_OK)
			g->objmap_read = set;
	}
	return st;
}
