/* Tiny scenes for the reference renderer's tests: built through rs_scene_add_mesh(, NULL),
 * packed with rs_bvh_build() + rs_pack_*(). Included by tests/test_trace_render*.c only. */
#ifndef TEST_TRACE_RENDER_FIXTURE_H
#define TEST_TRACE_RENDER_FIXTURE_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_pack.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_trace.h"

struct fx {
	struct rs_scene *scene;
	struct rs_packed packed;
};

static inline struct rs_scene *fx_scene(void)
{
	struct rs_scene *scene = NULL;
	assert_int_equal(rs_scene_create(NULL, &scene, NULL), RS_OK);
	return scene;
}

static inline uint32_t fx_material(struct rs_scene *scene, struct rs_material m)
{
	uint32_t id = 0;
	assert_int_equal(rs_scene_add_material(scene, &m, &id, NULL), RS_OK);
	return id;
}

static inline void fx_mesh(struct rs_scene *scene, const float *pos, size_t nv, const uint32_t *idx,
                           size_t nt, const float *normals, uint32_t material)
{
	struct rs_mesh_desc d = {.positions = pos,
	                         .vertex_count = nv,
	                         .normals = normals,
	                         .indices = idx,
	                         .triangle_count = nt,
	                         .material = material};
	assert_int_equal(rs_scene_add_mesh(scene, &d, NULL), RS_OK);
}

/* Axis-aligned rectangle at height `h` on axis `axis` (0..2), spanning [lo1, hi1] x
 * [lo2, hi2] on axes (axis+1)%3, (axis+2)%3, wound so that its geometric normal is +axis
 * (flip: -axis). Own vertices, so its computed normals are flat. */
static inline void fx_rect(struct rs_scene *scene, int axis, double h, double lo1, double hi1,
                           double lo2, double hi2, int flip, uint32_t material)
{
	int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
	float pos[12];
	const double uv[4][2] = {{lo1, lo2}, {hi1, lo2}, {hi1, hi2}, {lo1, hi2}};
	for (int k = 0; k < 4; ++k) {
		pos[k * 3 + axis] = (float)h;
		pos[k * 3 + a1] = (float)uv[k][0];
		pos[k * 3 + a2] = (float)uv[k][1];
	}
	const uint32_t up[6] = {0, 1, 2, 0, 2, 3}, down[6] = {0, 2, 1, 0, 3, 2};
	fx_mesh(scene, pos, 4, flip ? down : up, 2, NULL, material);
}

static inline void fx_quad(struct rs_scene *scene, int axis, double h, double lo, double hi,
                           int flip, uint32_t material)
{
	fx_rect(scene, axis, h, lo, hi, lo, hi, flip, material);
}

/* Closed axis-aligned box [lo, hi] with outward normals: 6 rectangles, 12 triangles. */
static inline void fx_box(struct rs_scene *scene, const double lo[3], const double hi[3],
                          uint32_t material)
{
	for (int a = 0; a < 3; ++a) {
		int a1 = (a + 1) % 3, a2 = (a + 2) % 3;
		fx_rect(scene, a, lo[a], lo[a1], hi[a1], lo[a2], hi[a2], 1, material);
		fx_rect(scene, a, hi[a], lo[a1], hi[a1], lo[a2], hi[a2], 0, material);
	}
}

static inline void fx_camera(struct rs_scene *scene, const double eye[3], const double target[3],
                             uint32_t size)
{
	struct rs_camera c = {.eye = {eye[0], eye[1], eye[2]},
	                      .target = {target[0], target[1], target[2]},
	                      .up = {0, 1, 0},
	                      .fov_y_deg = 45,
	                      .width = size,
	                      .height = size};
	if (fabs(target[0] - eye[0]) < 1e-9 && fabs(target[2] - eye[2]) < 1e-9) {
		c.up[1] = 0.0;
		c.up[2] = -1.0;
	}
	assert_int_equal(rs_scene_set_camera(scene, &c, NULL), RS_OK);
}

static inline void fx_light(struct rs_scene *scene, double x, double y, double z, double r,
                            double g, double b)
{
	struct rs_light l = {.position = {x, y, z}, .color = {r, g, b}};
	assert_int_equal(rs_scene_add_light(scene, &l, NULL), RS_OK);
}

/* Pack the scene with the given builder (the scene stays owned by fx). */
static inline void fx_pack(struct fx *fx, enum rs_bvh_builder builder)
{
	struct rs_bvh_desc bd = {.builder = builder};
	size_t tris = rs_scene_triangle_count(fx->scene);
	size_t cap = rs_bvh_node_bound(&bd, tris);
	struct rs_bvh_node *nodes = calloc(cap ? cap : 1, sizeof *nodes);
	uint32_t *order = calloc(tris ? tris : 1, sizeof *order);
	assert_non_null(nodes);
	assert_non_null(order);
	size_t node_count = 0;
	struct rs_error err;
	assert_int_equal(rs_bvh_build(&bd, rs_scene_positions(fx->scene),
	                              rs_scene_vertex_count(fx->scene), rs_scene_indices(fx->scene),
	                              tris, nodes, cap, order, &node_count, &err),
	                 RS_OK);
	assert_int_equal(rs_pack_layout(NULL, node_count, tris, rs_scene_material_count(fx->scene),
	                                &fx->packed, &err),
	                 RS_OK);
	assert_int_equal(rs_pack_alloc(&fx->packed, &err), RS_OK);
	assert_int_equal(rs_pack_scene(fx->scene, nodes, node_count, order, &fx->packed, &err),
	                 RS_OK);
	free(nodes);
	free(order);
}

static inline void fx_free(struct fx *fx)
{
	rs_pack_free(&fx->packed);
	rs_scene_destroy(&fx->scene);
}

/* A path from `origin` towards `towards` with the given passes and lights (0 = all). */
static inline struct rs_trace_path fx_path(const struct fx *fx, const double origin[3],
                                           const double towards[3], uint32_t passes,
                                           struct rs_trace_segment *segments)
{
	struct rs_ray ray = {
	    .origin = {origin[0], origin[1], origin[2]},
	    .dir = {towards[0] - origin[0], towards[1] - origin[1], towards[2] - origin[2]},
	    .tmin = 0.0,
	    .tmax = INFINITY,
	    .skip_slot = RS_NO_SLOT};
	struct rs_trace_desc desc = {.passes = passes};
	struct rs_trace_path path;
	struct rs_error err;
	assert_int_equal(
	    rs_trace_ray_path(fx->scene, &fx->packed, &desc, &ray, &path, segments, &err), RS_OK);
	return path;
}

#endif
