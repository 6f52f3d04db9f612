/* Reflective objects for inter-reflection environment mapping: union-find over the mirror
 * triangles, joined where corners sit at the same position (generated spheres repeat the
 * seam's vertices, so shared indices alone would cut them open). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_scene.h"

struct corner_sort {
	const double *pos;
	const uint32_t *idx;
};

/* qsort has no context argument; calls on different scenes may run on different threads at
 * once, so the context is per thread. */
static _Thread_local struct corner_sort sort_ctx;

static int by_position(const void *a, const void *b)
{
	const double *p = &sort_ctx.pos[3 * (size_t)sort_ctx.idx[*(const uint32_t *)a]];
	const double *q = &sort_ctx.pos[3 * (size_t)sort_ctx.idx[*(const uint32_t *)b]];
	for (int k = 0; k < 3; ++k)
		if (p[k] != q[k])
			return p[k] < q[k] ? -1 : 1;
	return 0;
}

static uint32_t find(uint32_t *parent, uint32_t t)
{
	while (parent[t] != t) {
		parent[t] = parent[parent[t]]; /* path halving keeps the trees flat */
		t = parent[t];
	}
	return t;
}

static void join(uint32_t *parent, uint32_t a, uint32_t b)
{
	a = find(parent, a);
	b = find(parent, b);
	/* The lower triangle becomes the root, so roots order objects by lowest triangle. */
	if (a < b)
		parent[b] = a;
	else if (b < a)
		parent[a] = b;
}

enum rs_status rs_scene_reflective_objects(const struct rs_scene *scene,
                                           uint32_t *object_of_triangle,
                                           struct rs_scene_object *objects, size_t capacity,
                                           size_t *count, struct rs_error *err)
{
	size_t tris = rs_scene_triangle_count(scene);
	const uint32_t *idx = rs_scene_indices(scene), *mat = rs_scene_triangle_materials(scene);
	const struct rs_material *mats = rs_scene_materials(scene);
	const double *pos = rs_scene_positions_f64(scene);
	*count = 0;
	uint32_t *parent = malloc((tris ? tris : 1) * sizeof(uint32_t));
	uint32_t *corners = malloc((tris ? 3 * tris : 1) * sizeof(uint32_t));
	uint32_t *object = malloc((tris ? tris : 1) * sizeof(uint32_t));
	if (!parent || !corners || !object) {
		free(parent);
		free(corners);
		free(object);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "scene: out of memory grouping mirrors");
	}
	size_t nc = 0;
	for (size_t t = 0; t < tris; ++t) {
		parent[t] = (uint32_t)t;
		if (mats[mat[t]].reflectance > 0.0f)
			for (uint32_t c = 0; c < 3; ++c)
				corners[nc++] = (uint32_t)(3 * t + c);
	}
	sort_ctx = (struct corner_sort){pos, idx};
	qsort(corners, nc, sizeof(uint32_t), by_position);
	for (size_t i = 1; i < nc; ++i) {
		uint32_t a = corners[i - 1] / 3, b = corners[i] / 3;
		if (mat[a] == mat[b] && by_position(&corners[i - 1], &corners[i]) == 0)
			join(parent, a, b);
	}
	/* Number the roots in triangle order, then the bounds and the sphere of each. */
	size_t n = 0;
	for (size_t t = 0; t < tris; ++t) {
		object[t] = RS_SCENE_NO_OBJECT;
		if (!(mats[mat[t]].reflectance > 0.0f))
			continue;
		uint32_t r = find(parent, (uint32_t)t);
		object[t] = r == t ? (uint32_t)n++ : object[r];
	}
	*count = n;
	size_t keep = n < capacity ? n : capacity;
	for (size_t o = 0; o < keep; ++o)
		objects[o] = (struct rs_scene_object){
		    .center = {INFINITY, INFINITY, INFINITY}, .radius = -INFINITY, .material = 0};
	/* center collects the low corner of the bounds, hi the high one. */
	double(*hi)[3] = keep ? malloc(keep * sizeof(*hi)) : NULL;
	enum rs_status st = RS_OK;
	if (keep && !hi)
		st = rs_error_set(err, RS_ERR_NO_MEMORY, "scene: out of memory grouping mirrors");
	for (size_t o = 0; st == RS_OK && o < keep; ++o)
		hi[o][0] = hi[o][1] = hi[o][2] = -INFINITY;
	for (size_t t = 0; st == RS_OK && t < tris; ++t) {
		uint32_t o = object[t];
		if (o == RS_SCENE_NO_OBJECT || o >= keep)
			continue;
		if (objects[o].triangle_count++ == 0)
			objects[o].material = mat[t];
		for (int c = 0; c < 3; ++c)
			for (int k = 0; k < 3; ++k) {
				double v = pos[3 * (size_t)idx[3 * t + (size_t)c] + (size_t)k];
				objects[o].center[k] = fmin(objects[o].center[k], v);
				hi[o][k] = fmax(hi[o][k], v);
			}
	}
	for (size_t o = 0; st == RS_OK && o < keep; ++o)
		for (int k = 0; k < 3; ++k)
			objects[o].center[k] = 0.5 * (objects[o].center[k] + hi[o][k]);
	for (size_t t = 0; st == RS_OK && t < tris; ++t) {
		uint32_t o = object[t];
		if (o == RS_SCENE_NO_OBJECT || o >= keep)
			continue;
		for (int c = 0; c < 3; ++c) {
			const double *v = &pos[3 * (size_t)idx[3 * t + (size_t)c]];
			double dx = v[0] - objects[o].center[0], dy = v[1] - objects[o].center[1],
			       dz = v[2] - objects[o].center[2];
			objects[o].radius =
			    fmax(objects[o].radius, sqrt(dx * dx + dy * dy + dz * dz));
		}
	}
	if (st == RS_OK && object_of_triangle)
		memcpy(object_of_triangle, object, tris * sizeof(uint32_t));
	free(hi);
	free(parent);
	free(corners);
	free(object);
	if (st == RS_OK && n > capacity)
		st = rs_error_set(err, RS_ERR_LIMIT, "scene: %zu reflective objects, room for %zu",
		                  n, capacity);
	return st;
}
