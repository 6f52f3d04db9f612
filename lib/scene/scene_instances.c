/* Prototype meshes and their instances (rs_scene_add_prototype, rs_scene_add_instance). An
 * instance is baked into world-space triangles through rs_scene_add_mesh(), so every packer
 * and tracer sees ordinary geometry; its record keeps the transform and its triangle range
 * for a two-level packing. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_scene.h"

#include "scene_internal.h"

static void free_prototype(struct rs_scene_prototype *p)
{
	free(p->positions);
	free(p->normals);
	free(p->indices);
}

enum rs_status rs_scene_add_prototype(struct rs_scene *scene, const struct rs_mesh_desc *mesh,
                                      uint32_t *out_id, struct rs_error *err)
{
	RS_ASSERT(scene && mesh);
	enum rs_status status = rs__scene_validate_mesh(scene, mesh, err);
	if (status != RS_OK)
		return status;
	if (scene->prototype_count >= RS_SCENE_MAX_PROTOTYPES)
		return rs_error_set(err, RS_ERR_LIMIT, "more than %u prototype meshes",
		                    RS_SCENE_MAX_PROTOTYPES);
	size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
	struct rs_scene_prototype p = {
	    .vertex_count = nv, .triangle_count = nt, .material = mesh->material};
	p.positions = malloc(nv * 3 * sizeof *p.positions);
	p.normals = malloc(nv * 3 * sizeof *p.normals);
	p.indices = malloc(nt * 3 * sizeof *p.indices);
	if (!p.positions || !p.normals || !p.indices ||
	    !rs__scene_grow((void **)&scene->prototypes, &scene->prototype_capacity,
	                    scene->prototype_count + 1, sizeof *scene->prototypes)) {
		free_prototype(&p);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory adding a prototype");
	}
	for (size_t i = 0; i < nv; ++i)
		rs__scene_mesh_position(mesh, i, p.positions + i * 3);
	size_t istride = mesh->index_stride ? mesh->index_stride : 3 * sizeof(uint32_t);
	for (size_t t = 0; t < nt; ++t)
		memcpy(p.indices + t * 3, (const char *)mesh->indices + t * istride,
		       3 * sizeof(uint32_t));
	if (mesh->normals) {
		size_t nstride = mesh->normal_stride ? mesh->normal_stride : 3 * sizeof(float);
		for (size_t i = 0; i < nv; ++i)
			memcpy(p.normals + i * 3, (const char *)mesh->normals + i * nstride,
			       3 * sizeof(float));
		rs_scene_normalize_normals(p.normals, nv);
	} else {
		/* the normals the same mesh would get from rs_scene_add_mesh() */
		if (!rs_scene_angle_weighted_normals(p.positions, p.indices, nt, 0, nv,
		                                     p.normals)) {
			free_prototype(&p);
			return rs_error_set(err, RS_ERR_NO_MEMORY,
			                    "out of memory computing a prototype's normals");
		}
	}
	if (out_id)
		*out_id = (uint32_t)scene->prototype_count;
	scene->prototypes[scene->prototype_count++] = p;
	return RS_OK;
}

static double det3(const double m[3][4])
{
	return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
	       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
	       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Cofactor matrix C of the 3x3 part: A^-1 = C^T / det and A^-T = C / det. */
static void cofactors(const double m[3][4], double c[3][3])
{
	for (int r = 0; r < 3; ++r)
		for (int k = 0; k < 3; ++k) {
			int r1 = (r + 1) % 3, r2 = (r + 2) % 3, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
			c[r][k] = m[r1][k1] * m[r2][k2] - m[r1][k2] * m[r2][k1];
		}
}

/* Resolve (all zero -> identity) and check a transform; fills the world -> object inverse. */
static enum rs_status check_transform(const double in[3][4], double out[3][4], double inverse[3][4],
                                      double *out_det, struct rs_error *err)
{
	bool zero = true;
	for (int r = 0; r < 3; ++r)
		for (int k = 0; k < 4; ++k) {
			if (!isfinite(in[r][k]))
				return rs_error_set(
				    err, RS_ERR_BAD_DATA,
				    "instance transform [%d][%d] is NaN or infinite", r, k);
			zero = zero && in[r][k] == 0.0;
		}
	for (int r = 0; r < 3; ++r)
		for (int k = 0; k < 4; ++k)
			out[r][k] = zero ? (r == k ? 1.0 : 0.0) : in[r][k];
	double scale = 0.0;
	for (int r = 0; r < 3; ++r)
		for (int k = 0; k < 3; ++k)
			scale = fmax(scale, fabs(out[r][k]));
	double det = det3(out);
	/* relative to the scale cubed, so a uniformly tiny but regular scale is kept */
	if (!isfinite(det) || !(fabs(det) > 1e-12 * scale * scale * scale))
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "instance transform is singular (det %g at scale %g)", det,
		                    scale);
	double c[3][3];
	cofactors(out, c);
	for (int r = 0; r < 3; ++r) {
		for (int k = 0; k < 3; ++k)
			inverse[r][k] = c[k][r] / det;
		inverse[r][3] = 0.0;
		for (int k = 0; k < 3; ++k)
			inverse[r][3] -= inverse[r][k] * out[k][3];
	}
	*out_det = det;
	return RS_OK;
}

/* Prototype p through m (det: of its 3x3 part): world positions in double, normals by the
 * inverse transpose C / det (the sign of det matters; renormalised when stored). */
static void bake(const struct rs_scene_prototype *p, const double m[3][4], double det, double *pos,
                 float *nrm)
{
	double c[3][3];
	cofactors(m, c);
	for (size_t i = 0; i < p->vertex_count; ++i) {
		const double *o = p->positions + i * 3;
		const float *n = p->normals + i * 3;
		for (int r = 0; r < 3; ++r) {
			pos[i * 3 + r] = m[r][0] * o[0] + m[r][1] * o[1] + m[r][2] * o[2] + m[r][3];
			nrm[i * 3 + r] =
			    (float)((c[r][0] * n[0] + c[r][1] * n[1] + c[r][2] * n[2]) / det);
		}
	}
}

static enum rs_status bake_buffers(size_t nv, double **pos, float **nrm, struct rs_error *err)
{
	*pos = malloc(nv * 3 * sizeof **pos);
	*nrm = malloc(nv * 3 * sizeof **nrm);
	if (*pos && *nrm)
		return RS_OK;
	free(*pos);
	free(*nrm);
	*pos = NULL;
	*nrm = NULL;
	return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory baking an instance");
}

enum rs_status rs_scene_add_instance(struct rs_scene *scene, const struct rs_instance_desc *desc,
                                     uint32_t *out_id, struct rs_error *err)
{
	RS_ASSERT(scene && desc);
	if (desc->mesh >= scene->prototype_count)
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "instance of prototype mesh %u, the scene has %zu", desc->mesh,
		                    scene->prototype_count);
	if (desc->override_material && desc->material >= scene->material_count)
		return rs_error_set(err, RS_ERR_BAD_DATA, "instance uses unknown material %u",
		                    desc->material);
	if (scene->instance_count >= UINT32_MAX)
		return rs_error_set(err, RS_ERR_LIMIT, "too many instances");
	struct rs_scene_instance inst = {.mesh = desc->mesh};
	double det = 0.0;
	enum rs_status status =
	    check_transform(desc->transform, inst.transform, inst.inverse, &det, err);
	if (status != RS_OK)
		return status;
	const struct rs_scene_prototype *p = &scene->prototypes[desc->mesh];
	inst.material = desc->override_material ? desc->material : p->material;
	inst.first_triangle = (uint32_t)scene->triangle_count;
	inst.triangle_count = (uint32_t)p->triangle_count;
	if (!rs__scene_grow((void **)&scene->instances, &scene->instance_capacity,
	                    scene->instance_count + 1, sizeof *scene->instances) ||
	    !rs__scene_grow((void **)&scene->instance_bounds, &scene->instance_bounds_capacity,
	                    scene->instance_count + 1, sizeof *scene->instance_bounds))
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory adding an instance");
	size_t nv = p->vertex_count, nt = p->triangle_count;
	double *pos = NULL;
	float *nrm = NULL;
	uint32_t *idx = malloc(nt * 3 * sizeof *idx);
	status = idx ? bake_buffers(nv, &pos, &nrm, err)
	             : rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory baking an instance");
	if (status != RS_OK) {
		free(idx);
		return status;
	}
	bake(p, inst.transform, det, pos, nrm);
	/* A mirror turns e1 x e2 against the transformed normal: wind the other way so a
	 * triangle's geometric normal faces the side its vertex normals do, as in the prototype. */
	bool mirror = det < 0.0;
	for (size_t t = 0; t < nt; ++t) {
		const uint32_t *tri = p->indices + t * 3;
		idx[t * 3] = tri[0];
		idx[t * 3 + 1] = tri[mirror ? 2 : 1];
		idx[t * 3 + 2] = tri[mirror ? 1 : 2];
	}
	/* rs_scene_add_mesh renormalises the normals and refuses positions out of float range */
	struct rs_mesh_desc baked = {.positions_f64 = pos,
	                             .vertex_count = nv,
	                             .normals = nrm,
	                             .indices = idx,
	                             .triangle_count = nt,
	                             .material = inst.material};
	status = rs__scene_append_mesh(scene, &baked,
	                               &scene->instance_bounds[scene->instance_count], err);
	free(pos);
	free(nrm);
	free(idx);
	if (status != RS_OK)
		return status;
	if (out_id)
		*out_id = (uint32_t)scene->instance_count;
	scene->instances[scene->instance_count++] = inst;
	return RS_OK;
}

enum rs_status rs_scene_set_instance_transform(struct rs_scene *scene, uint32_t id,
                                               const double transform[3][4], struct rs_error *err)
{
	RS_ASSERT(scene && transform);
	if (id >= scene->instance_count)
		return rs_error_set(err, RS_ERR_BAD_DATA, "unknown instance %u, the scene has %zu",
		                    id, scene->instance_count);
	struct rs_scene_instance *inst = &scene->instances[id];
	double m[3][4], inverse[3][4], det = 0.0;
	enum rs_status status = check_transform(transform, m, inverse, &det, err);
	if (status != RS_OK)
		return status;
	if ((det < 0.0) != (det3(inst->transform) < 0.0))
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "instance %u: the new transform %s where the old one %s (the "
		                    "baked winding would change; add another instance)",
		                    id, det < 0.0 ? "mirrors" : "does not mirror",
		                    det < 0.0 ? "did not" : "did");
	const struct rs_scene_prototype *p = &scene->prototypes[inst->mesh];
	size_t nv = p->vertex_count;
	/* the baked vertices are contiguous, and a triangle's first index is never swapped */
	size_t v0 = scene->indices[(size_t)inst->first_triangle * 3] - p->indices[0];
	double *pos = NULL;
	float *nrm = NULL;
	status = bake_buffers(nv, &pos, &nrm, err);
	if (status != RS_OK)
		return status;
	bake(p, m, det, pos, nrm);
	for (size_t i = 0; i < nv * 3; ++i)
		if (!isfinite(pos[i]) || fabs(pos[i]) > FLT_MAX) {
			free(pos);
			free(nrm);
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "instance %u: vertex %zu would have a NaN, infinite or "
			                    "too large coordinate",
			                    id, i / 3);
		}
	struct rs_bounds box = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
	for (size_t i = 0; i < nv; ++i) {
		rs__scene_bounds_add(&box, pos + i * 3);
		for (int a = 0; a < 3; ++a)
			scene->positions[(v0 + i) * 3 + a] = (float)pos[i * 3 + a];
	}
	memcpy(scene->positions_f64 + v0 * 3, pos, nv * 3 * sizeof *pos);
	memcpy(scene->normals + v0 * 3, nrm, nv * 3 * sizeof *nrm);
	rs_scene_normalize_normals(scene->normals + v0 * 3, nv);
	free(pos);
	free(nrm);
	memcpy(inst->transform, m, sizeof m);
	memcpy(inst->inverse, inverse, sizeof inverse);
	scene->instance_bounds[id] = box;
	scene->bounds_stale = true;
	return RS_OK;
}

size_t rs_scene_prototype_count(const struct rs_scene *scene)
{
	return scene->prototype_count;
}

size_t rs_scene_instance_count(const struct rs_scene *scene)
{
	return scene->instance_count;
}

const struct rs_scene_instance *rs_scene_instances(const struct rs_scene *scene)
{
	return scene->instances;
}

void rs_scene_prototype_mesh(const struct rs_scene *scene, uint32_t id, struct rs_mesh_desc *out)
{
	RS_ASSERT(scene && out && id < scene->prototype_count);
	const struct rs_scene_prototype *p = &scene->prototypes[id];
	*out = (struct rs_mesh_desc){.positions_f64 = p->positions,
	                             .vertex_count = p->vertex_count,
	                             .normals = p->normals,
	                             .indices = p->indices,
	                             .triangle_count = p->triangle_count,
	                             .material = p->material};
}
