/* The scene container: copies caller geometry in, validates it, computes normals. */
#include "raystream/rs_scene.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

#define RS_SCENE_DEFAULT_MAX_TRIANGLES ((size_t)(1u << 24) - 1u)

static const float rs_default_face_colors[6][3] = {
    {0.80f, 0.35f, 0.30f}, {0.30f, 0.65f, 0.35f}, {0.55f, 0.70f, 0.90f},
    {0.45f, 0.40f, 0.35f}, {0.85f, 0.80f, 0.40f}, {0.55f, 0.40f, 0.75f},
};

enum rs_status rs_scene_create(const struct rs_scene_desc *desc, struct rs_scene **out,
                               struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	struct rs_scene *scene = calloc(1, sizeof *scene);
	if (!scene)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory creating a scene");
	scene->max_triangles =
	    desc && desc->max_triangles ? desc->max_triangles : RS_SCENE_DEFAULT_MAX_TRIANGLES;
	scene->ambient = 0.1;
	for (int a = 0; a < 3; ++a) {
		scene->mesh_bounds.lo[a] = INFINITY;
		scene->mesh_bounds.hi[a] = -INFINITY;
	}
	scene->camera.eye[2] = 10.0;
	scene->camera.up[1] = 1.0;
	memcpy(scene->environment.face_color, rs_default_face_colors,
	       sizeof rs_default_face_colors);
	*out = scene;
	return RS_OK;
}

void rs_scene_destroy(struct rs_scene **scene)
{
	if (!scene || !*scene)
		return;
	struct rs_scene *s = *scene;
	free(s->positions);
	free(s->positions_f64);
	free(s->normals);
	free(s->indices);
	free(s->triangle_materials);
	free(s->materials);
	free(s->lights);
	for (size_t i = 0; i < s->prototype_count; ++i) {
		free(s->prototypes[i].positions);
		free(s->prototypes[i].normals);
		free(s->prototypes[i].indices);
	}
	free(s->prototypes);
	free(s->instances);
	free(s->instance_bounds);
	free(s);
	*scene = NULL;
}

static int finite3(const float *v)
{
	return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* Vertex i of the mesh in double, whichever precision it was given in. */
void rs__scene_mesh_position(const struct rs_mesh_desc *mesh, size_t i, double out[3])
{
	if (mesh->positions_f64) {
		size_t stride = mesh->position_stride ? mesh->position_stride : 3 * sizeof(double);
		memcpy(out, (const char *)mesh->positions_f64 + i * stride, 3 * sizeof(double));
		return;
	}
	size_t stride = mesh->position_stride ? mesh->position_stride : 3 * sizeof(float);
	float f[3];
	memcpy(f, (const char *)mesh->positions + i * stride, sizeof f);
	for (int a = 0; a < 3; ++a)
		out[a] = f[a];
}

/* Grow an array to hold `count` elements of `size` bytes, doubling capacity. */
int rs__scene_grow(void **array, size_t *capacity, size_t count, size_t size)
{
	if (count <= *capacity)
		return 1;
	size_t cap = *capacity ? *capacity : 16;
	while (cap < count) {
		if (cap > SIZE_MAX / 2 / size)
			return 0;
		cap *= 2;
	}
	void *p = realloc(*array, cap * size);
	if (!p)
		return 0;
	*array = p;
	*capacity = cap;
	return 1;
}

enum rs_status rs_scene_add_material(struct rs_scene *scene, const struct rs_material *material,
                                     uint32_t *out_id, struct rs_error *err)
{
	RS_ASSERT(scene && material);
	const float *m = material->diffuse;
	const float v[] = {m[0],
	                   m[1],
	                   m[2],
	                   material->specular,
	                   material->shininess,
	                   material->reflectance,
	                   material->transmittance,
	                   material->ior};
	for (size_t i = 0; i < sizeof v / sizeof v[0]; ++i)
		if (!isfinite(v[i]) || v[i] < 0.0f)
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "material %zu: value %zu is negative or not finite",
			                    scene->material_count, i);
	if (material->ior != 0.0f && material->ior < 1e-3f)
		return rs_error_set(err, RS_ERR_BAD_DATA, "material %zu: ior %g is too small",
		                    scene->material_count, (double)material->ior);
	if (scene->material_count >= (1u << 24))
		return rs_error_set(err, RS_ERR_LIMIT, "too many materials");
	if (!rs__scene_grow((void **)&scene->materials, &scene->material_capacity,
	                    scene->material_count + 1, sizeof *scene->materials))
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory adding a material");
	scene->materials[scene->material_count] = *material;
	if (out_id)
		*out_id = (uint32_t)scene->material_count;
	scene->material_count++;
	return RS_OK;
}

static const float *strided(const float *base, size_t stride, size_t i)
{
	return (const float *)((const char *)base + i * (stride ? stride : 3 * sizeof(float)));
}

static const uint32_t *strided_u32(const uint32_t *base, size_t stride, size_t i)
{
	return (const uint32_t *)((const char *)base +
	                          i * (stride ? stride : 3 * sizeof(uint32_t)));
}

enum rs_status rs__scene_validate_mesh(const struct rs_scene *scene,
                                       const struct rs_mesh_desc *mesh, struct rs_error *err)
{
	if (!mesh->positions == !mesh->positions_f64 || !mesh->indices)
		return rs_error_set(
		    err, RS_ERR_INVALID,
		    "mesh needs exactly one of positions/positions_f64, and indices");
	if (mesh->triangle_count == 0)
		return rs_error_set(err, RS_ERR_BAD_DATA, "mesh has zero triangles");
	if (mesh->vertex_count == 0 || mesh->vertex_count > UINT32_MAX)
		return rs_error_set(err, RS_ERR_BAD_DATA, "mesh has %zu vertices",
		                    mesh->vertex_count);
	if (mesh->material >= scene->material_count)
		return rs_error_set(err, RS_ERR_BAD_DATA, "mesh uses unknown material %u",
		                    mesh->material);
	if (mesh->triangle_count > scene->max_triangles - scene->triangle_count)
		return rs_error_set(err, RS_ERR_LIMIT, "scene would have more than %zu triangles",
		                    scene->max_triangles);
	for (size_t i = 0; i < mesh->vertex_count; ++i) {
		double p[3];
		rs__scene_mesh_position(mesh, i, p);
		/* also refuses doubles that would overflow to an infinite float */
		for (int a = 0; a < 3; ++a)
			if (!isfinite(p[a]) || fabs(p[a]) > FLT_MAX)
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "vertex %zu has a NaN, infinite or too large "
				                    "coordinate",
				                    i);
		if (mesh->normals && !finite3(strided(mesh->normals, mesh->normal_stride, i)))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "normal %zu has a NaN or infinite component", i);
	}
	for (size_t t = 0; t < mesh->triangle_count; ++t) {
		const uint32_t *tri = strided_u32(mesh->indices, mesh->index_stride, t);
		for (int k = 0; k < 3; ++k)
			if (tri[k] >= mesh->vertex_count)
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "triangle %zu uses vertex %u of %zu", t, tri[k],
				                    mesh->vertex_count);
	}
	return RS_OK;
}

void rs__scene_bounds_add(struct rs_bounds *b, const double p[3])
{
	for (int a = 0; a < 3; ++a) {
		b->lo[a] = p[a] < b->lo[a] ? p[a] : b->lo[a];
		b->hi[a] = p[a] > b->hi[a] ? p[a] : b->hi[a];
	}
}

enum rs_status rs_scene_add_mesh(struct rs_scene *scene, const struct rs_mesh_desc *mesh,
                                 struct rs_error *err)
{
	RS_ASSERT(scene && mesh);
	struct rs_bounds added;
	enum rs_status status = rs__scene_append_mesh(scene, mesh, &added, err);
	if (status == RS_OK) {
		rs__scene_bounds_add(&scene->mesh_bounds, added.lo);
		rs__scene_bounds_add(&scene->mesh_bounds, added.hi);
	}
	return status;
}

enum rs_status rs__scene_append_mesh(struct rs_scene *scene, const struct rs_mesh_desc *mesh,
                                     struct rs_bounds *added, struct rs_error *err)
{
	RS_ASSERT(scene && mesh);
	enum rs_status status = rs__scene_validate_mesh(scene, mesh, err);
	if (status != RS_OK)
		return status;
	size_t v0 = scene->vertex_count, t0 = scene->triangle_count;
	size_t vn = v0 + mesh->vertex_count, tn = t0 + mesh->triangle_count;
	if (vn > UINT32_MAX ||
	    !rs__scene_grow((void **)&scene->positions, &scene->position_capacity, vn * 3,
	                    sizeof(float)) ||
	    !rs__scene_grow((void **)&scene->positions_f64, &scene->position_f64_capacity, vn * 3,
	                    sizeof(double)) ||
	    !rs__scene_grow((void **)&scene->normals, &scene->normal_capacity, vn * 3,
	                    sizeof(float)) ||
	    !rs__scene_grow((void **)&scene->indices, &scene->index_capacity, tn * 3,
	                    sizeof(uint32_t)) ||
	    !rs__scene_grow((void **)&scene->triangle_materials, &scene->triangle_material_capacity,
	                    tn, sizeof(uint32_t)))
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory adding %zu triangles",
		                    mesh->triangle_count);
	for (size_t i = 0; i < mesh->vertex_count; ++i) {
		double *p = scene->positions_f64 + (v0 + i) * 3;
		rs__scene_mesh_position(mesh, i, p);
		for (int a = 0; a < 3; ++a)
			scene->positions[(v0 + i) * 3 + a] = (float)p[a];
	}
	for (size_t t = 0; t < mesh->triangle_count; ++t) {
		const uint32_t *tri = strided_u32(mesh->indices, mesh->index_stride, t);
		for (int k = 0; k < 3; ++k)
			scene->indices[(t0 + t) * 3 + k] = (uint32_t)v0 + tri[k];
		scene->triangle_materials[t0 + t] = mesh->material;
	}
	if (mesh->normals) {
		for (size_t i = 0; i < mesh->vertex_count; ++i)
			memcpy(scene->normals + (v0 + i) * 3,
			       strided(mesh->normals, mesh->normal_stride, i), 3 * sizeof(float));
		rs_scene_normalize_normals(scene->normals + v0 * 3, mesh->vertex_count);
	} else if (!rs_scene_angle_weighted_normals(scene->positions_f64, scene->indices + t0 * 3,
	                                            mesh->triangle_count, v0, mesh->vertex_count,
	                                            scene->normals + v0 * 3)) {
		/* Counts are not advanced yet, so the scene is unchanged. */
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory computing normals");
	}
	scene->vertex_count = vn;
	scene->triangle_count = tn;
	for (int a = 0; a < 3; ++a) {
		added->lo[a] = INFINITY;
		added->hi[a] = -INFINITY;
		if (v0 == 0) {
			scene->bounds.lo[a] = INFINITY;
			scene->bounds.hi[a] = -INFINITY;
		}
	}
	for (size_t i = v0; i < vn; ++i)
		rs__scene_bounds_add(added, scene->positions_f64 + i * 3);
	/* while stale, rs_scene_bounds() forms the union from the parts instead */
	rs__scene_bounds_add(&scene->bounds, added->lo);
	rs__scene_bounds_add(&scene->bounds, added->hi);
	return RS_OK;
}
