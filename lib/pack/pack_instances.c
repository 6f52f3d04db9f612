/* Two-level packing (rs_pack_instances): a BLAS per prototype mesh in its own space and a TLAS
 * over the instances' world boxes, each built and packed by the one-level code (rs_bvh_build,
 * rs_pack_scene) on a scratch scene, so both levels have exactly the node formats, directional
 * orders and bounds the walks already read. */
#include <float.h>
#include <stdbool.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_pack.h"

#include "pack_internal.h"

/* Build and pack the triangles of `scene` (a scratch scene) into *out. */
static enum rs_status build_and_pack(const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                     const struct rs_pack_desc *pack, struct rs_packed *out,
                                     double *build_ms, double *pack_ms, struct rs_error *err)
{
	size_t tris = rs_scene_triangle_count(scene);
	size_t cap = rs_bvh_node_bound(bvh, tris);
	struct rs_bvh_node *nodes = malloc((cap ? cap : 1) * sizeof *nodes);
	uint32_t *order = malloc((tris ? tris : 1) * sizeof *order);
	size_t node_count = 0;
	enum rs_status status = RS_OK;
	if (!nodes || !order)
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for a BVH");
	double t0 = rs_now_ms();
	if (status == RS_OK)
		status = rs_bvh_build(bvh, rs_scene_positions(scene), rs_scene_vertex_count(scene),
		                      rs_scene_indices(scene), tris, nodes, cap, order, &node_count,
		                      err);
	double t1 = rs_now_ms();
	*build_ms += t1 - t0;
	if (status == RS_OK)
		status = rs_pack_layout(pack, node_count, tris, rs_scene_material_count(scene), out,
		                        err);
	if (status == RS_OK)
		status = rs_pack_alloc(out, err);
	if (status == RS_OK)
		status = rs_pack_scene(scene, nodes, node_count, order, out, err);
	*pack_ms += rs_now_ms() - t1;
	if (status != RS_OK)
		rs_pack_free(out);
	free(nodes);
	free(order);
	return status;
}

/* A scratch scene with the source's materials (so material ids keep their meaning). */
static enum rs_status scratch_scene(const struct rs_scene *src, struct rs_scene **out,
                                    struct rs_error *err)
{
	enum rs_status status = rs_scene_create(NULL, out, err);
	const struct rs_material *m = rs_scene_materials(src);
	for (size_t i = 0; status == RS_OK && i < rs_scene_material_count(src); i++)
		status = rs_scene_add_material(*out, &m[i], NULL, err);
	static const struct rs_material plain;
	if (status == RS_OK && rs_scene_material_count(src) == 0)
		status = rs_scene_add_material(*out, &plain, NULL, err);
	return status;
}

/* The power of two that brings a magnitude outside [2^-10, 2^10] into [1, 2); 1 for one
 * inside (whose packed bits then stay as they were), zero or not finite. Used for what the
 * kernels compute with in fp32 that the scene's units do not bound (docs/bvh.md
 * "Instances", R7):
 * - a BLAS frame: a prototype modelled at 1e20 or 1e-14 units, scaled back to a normal world
 *   by its instances, overflowed or flushed the watertight test's products in its frame
 *   while the world frame was fine; scaled by this power of two, positions, origin, grid and
 *   transforms scale exactly, so the walk is the same;
 * - a normal matrix: only its direction counts (the normals are made unit), but an entry of
 *   1e21 overflowed the length. */
static double unit_power_of_two(double magnitude)
{
	if (!(magnitude > 0.0) || !isfinite(magnitude) ||
	    (magnitude >= 0x1p-10 && magnitude <= 0x1p10))
		return 1.0;
	return ldexp(1.0, -ilogb(magnitude));
}

static double mesh_half_extent(const struct rs_mesh_desc *mesh)
{
	struct rs_bounds b;
	for (int a = 0; a < 3; a++) {
		b.lo[a] = INFINITY;
		b.hi[a] = -INFINITY;
	}
	for (size_t v = 0; v < mesh->vertex_count; v++)
		for (int a = 0; a < 3; a++) {
			b.lo[a] = fmin(b.lo[a], mesh->positions_f64[v * 3 + a]);
			b.hi[a] = fmax(b.hi[a], mesh->positions_f64[v * 3 + a]);
		}
	double half = 0.0;
	for (int a = 0; a < 3; a++)
		if (b.hi[a] >= b.lo[a])
			half = fmax(half, 0.5 * (b.hi[a] - b.lo[a]));
	return half;
}

/* Build and pack one mesh (object space) as BLAS k, in its frame scaled by
 * unit_power_of_two() of its half extent:
 * the scale into out->mesh_scale[k], its object-space box into mesh_bounds[k]. */
static enum rs_status pack_mesh(const struct rs_scene *scene, const struct rs_mesh_desc *mesh,
                                const struct rs_bvh_desc *bvh, const struct rs_pack_desc *pack,
                                struct rs_packed_instances *out, uint32_t k,
                                struct rs_bounds *mesh_bounds, struct rs_error *err)
{
	double scale = unit_power_of_two(mesh_half_extent(mesh)), pack_ms = 0.0;
	double *scaled = NULL;
	struct rs_mesh_desc d = *mesh;
	if (scale != 1.0) {
		scaled = malloc((mesh->vertex_count ? mesh->vertex_count : 1) * 3 * sizeof *scaled);
		if (!scaled)
			return rs_error_set(err, RS_ERR_NO_MEMORY,
			                    "pack: out of memory for a mesh");
		for (size_t i = 0; i < mesh->vertex_count * 3; i++)
			scaled[i] = mesh->positions_f64[i] * scale;
		d.positions_f64 = scaled;
	}
	struct rs_scene *s = NULL;
	enum rs_status status = scratch_scene(scene, &s, err);
	if (status == RS_OK)
		status = rs_scene_add_mesh(s, &d, err);
	if (status == RS_OK)
		status =
		    build_and_pack(s, bvh, pack, &out->meshes[k], &out->build_ms, &pack_ms, err);
	if (status == RS_OK) {
		rs_scene_bounds(s, &mesh_bounds[k]);
		for (int a = 0; a < 3; a++) {
			mesh_bounds[k].lo[a] /= scale;
			mesh_bounds[k].hi[a] /= scale;
		}
		out->mesh_scale[k] = scale;
	}
	rs_scene_destroy(&s);
	free(scaled);
	return status;
}

static enum rs_status pack_meshes(const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                  const struct rs_pack_desc *pack, struct rs_packed_instances *out,
                                  struct rs_bounds *mesh_bounds, struct rs_error *err)
{
	enum rs_status status = RS_OK;
	uint32_t protos = (uint32_t)rs_scene_prototype_count(scene);
	for (uint32_t k = 0; status == RS_OK && k < protos; k++) {
		struct rs_mesh_desc mesh;
		rs_scene_prototype_mesh(scene, k, &mesh);
		status = pack_mesh(scene, &mesh, bvh, pack, out, k, mesh_bounds, err);
	}
	return status;
}

/* The triangles outside every instance as one more mesh (world space): runs of one material
 * each become a mesh of their own vertices; loose_ids[local] = scene id. */
static enum rs_status pack_loose(const struct rs_scene *scene, const bool *covered,
                                 const struct rs_bvh_desc *bvh, const struct rs_pack_desc *pack,
                                 struct rs_packed_instances *out, struct rs_bounds *bounds,
                                 struct rs_error *err)
{
	size_t tris = rs_scene_triangle_count(scene), verts = rs_scene_vertex_count(scene);
	const uint32_t *idx = rs_scene_indices(scene), *mat = rs_scene_triangle_materials(scene);
	const double *pos = rs_scene_positions_f64(scene);
	const float *nrm = rs_scene_normals(scene);
	uint32_t *remap = malloc((verts ? verts : 1) * sizeof *remap);
	size_t *stamp = calloc(verts ? verts : 1, sizeof *stamp);
	double *rp = malloc((tris * 3 + 1) * 3 * sizeof *rp);
	float *rn = malloc((tris * 3 + 1) * 3 * sizeof *rn);
	uint32_t *ri = malloc((tris + 1) * 3 * sizeof *ri);
	struct rs_scene *s = NULL;
	enum rs_status status = RS_OK;
	double pack_ms = 0.0;
	if (!remap || !stamp || !rp || !rn || !ri)
		status =
		    rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for loose triangles");
	if (status == RS_OK)
		status = scratch_scene(scene, &s, err);
	size_t run = 0, local = 0;
	for (size_t t = 0; status == RS_OK && t < tris;) {
		if (covered[t]) {
			t++;
			continue;
		}
		/* one run: consecutive loose triangles of one material */
		size_t nv = 0, nt = 0;
		run++;
		uint32_t m = mat[t];
		for (; t < tris && !covered[t] && mat[t] == m; t++, nt++) {
			out->loose_ids[local++] = (uint32_t)t;
			for (int k = 0; k < 3; k++) {
				uint32_t v = idx[t * 3 + k];
				if (stamp[v] != run) {
					stamp[v] = run;
					remap[v] = (uint32_t)nv;
					memcpy(rp + nv * 3, pos + (size_t)v * 3, 3 * sizeof *rp);
					memcpy(rn + nv * 3, nrm + (size_t)v * 3, 3 * sizeof *rn);
					nv++;
				}
				ri[nt * 3 + k] = remap[v];
			}
		}
		struct rs_mesh_desc d = {.positions_f64 = rp,
		                         .vertex_count = nv,
		                         .normals = rn,
		                         .indices = ri,
		                         .triangle_count = nt,
		                         .material = m};
		status = rs_scene_add_mesh(s, &d, err);
	}
	if (status == RS_OK)
		status = build_and_pack(s, bvh, pack, &out->meshes[out->mesh_count - 1],
		                        &out->build_ms, &pack_ms, err);
	if (status == RS_OK) {
		rs_scene_bounds(s, bounds);
		/* world space: the frame R7 already bounds (rs_trace_frame_reach) */
		out->mesh_scale[out->mesh_count - 1] = 1.0;
	}
	rs_scene_destroy(&s);
	free(remap);
	free(stamp);
	free(rp);
	free(rn);
	free(ri);
	return status;
}

/* Instance i's world box: the 8 corners of its mesh's object box through the transform. */
static void instance_box(const struct rs_scene_instance *inst, const struct rs_bounds *b,
                         double lo[3], double hi[3])
{
	for (int a = 0; a < 3; a++) {
		lo[a] = INFINITY;
		hi[a] = -INFINITY;
	}
	for (int c = 0; c < 8; c++) {
		double p[3] = {c & 1 ? b->hi[0] : b->lo[0], c & 2 ? b->hi[1] : b->lo[1],
		               c & 4 ? b->hi[2] : b->lo[2]};
		for (int r = 0; r < 3; r++) {
			const double *m = inst->transform[r];
			double w = m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3];
			lo[r] = fmin(lo[r], w);
			hi[r] = fmax(hi[r], w);
		}
	}
}

/* The TLAS over the n instances' world boxes into *top; its build and pack times into
 * build_ms and pack_ms. */
static enum rs_status pack_top(const struct rs_scene *scene, const struct rs_scene_instance *inst,
                               uint32_t n, const struct rs_bvh_desc *bvh,
                               const struct rs_pack_desc *pack, const struct rs_bounds *mesh_bounds,
                               struct rs_packed *top, double *build_ms, double *pack_ms,
                               struct rs_error *err)
{
	double *pos = malloc((size_t)n * 9 * sizeof *pos);
	uint32_t *idx = malloc((size_t)n * 3 * sizeof *idx);
	if (!pos || !idx) {
		free(pos);
		free(idx);
		return rs_error_set(err, RS_ERR_NO_MEMORY,
		                    "pack: out of memory for instance boxes");
	}
	double all_lo[3] = {INFINITY, INFINITY, INFINITY},
	       all_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
	for (uint32_t i = 0; i < n; i++) {
		double *lo = pos + i * 9, *hi = lo + 3;
		instance_box(&inst[i], &mesh_bounds[inst[i].mesh], lo, hi);
		for (int a = 0; a < 3; a++) {
			all_lo[a] = fmin(all_lo[a], lo[a]);
			all_hi[a] = fmax(all_hi[a], hi[a]);
		}
	}
	for (uint32_t i = 0; i < n; i++) {
		double *lo = pos + i * 9, *hi = lo + 3, *mid = lo + 6;
		for (int a = 0; a < 3; a++) {
			/* Packing rounds each coordinate, relative to the TLAS's centre (within the
			 * scene's extent of it), to float: one float ulp of the extent covers that,
			 * and 1e-12 relative covers the double corner transform. */
			double w = 2.0 * FLT_EPSILON * (all_hi[a] - all_lo[a]) +
			           1e-12 * (fabs(lo[a]) + fabs(hi[a])) + FLT_MIN;
			lo[a] -= w;
			hi[a] += w;
			mid[a] = 0.5 * (lo[a] + hi[a]);
		}
		idx[i * 3] = i * 3;
		idx[i * 3 + 1] = i * 3 + 1;
		idx[i * 3 + 2] = i * 3 + 2;
	}
	struct rs_scene *s = NULL;
	enum rs_status status = scratch_scene(scene, &s, err);
	/* normals are given (zero-area triangles have none to compute): any unit vector */
	float *nrm = status == RS_OK ? calloc((size_t)n * 9, sizeof *nrm) : NULL;
	if (status == RS_OK && !nrm)
		status =
		    rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for instance boxes");
	for (size_t v = 0; nrm && v < (size_t)n * 3; v++)
		nrm[v * 3 + 1] = 1.0f;
	struct rs_mesh_desc boxes = {.positions_f64 = pos,
	                             .vertex_count = (size_t)n * 3,
	                             .normals = nrm,
	                             .indices = idx,
	                             .triangle_count = n};
	if (status == RS_OK)
		status = rs_scene_add_mesh(s, &boxes, err);
	if (status == RS_OK)
		status = build_and_pack(s, bvh, pack, top, build_ms, pack_ms, err);
	rs_scene_destroy(&s);
	free(nrm);
	free(pos);
	free(idx);
	return status;
}

/* The scene's instances, then (loose) the loose BLAS's identity instance of mesh `protos`. */
static struct rs_scene_instance *instance_list(const struct rs_scene *scene, bool loose,
                                               struct rs_error *err)
{
	size_t ns = rs_scene_instance_count(scene);
	struct rs_scene_instance *inst = malloc((ns + loose) * sizeof *inst);
	if (!inst) {
		rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for instances");
		return NULL;
	}
	memcpy(inst, rs_scene_instances(scene), ns * sizeof *inst);
	if (loose) {
		struct rs_scene_instance id = {.mesh = (uint32_t)rs_scene_prototype_count(scene)};
		for (int r = 0; r < 3; r++)
			id.transform[r][r] = id.inverse[r][r] = 1.0;
		inst[ns] = id;
	}
	return inst;
}

/* Per instance: its mesh, first triangle, world -> BLAS frame (object space scaled by the
 * mesh's power of two, less its packed origin) and normal matrix. */
static void set_transforms(struct rs_packed_instances *out, const struct rs_scene_instance *inst)
{
	for (size_t i = 0; i < out->instance_count; i++) {
		const double *o = out->meshes[inst[i].mesh].origin;
		double scale = out->mesh_scale[inst[i].mesh], largest = 0.0;
		out->mesh[i] = inst[i].mesh;
		out->first_triangle[i] = inst[i].first_triangle;
		for (int r = 0; r < 3; r++) {
			for (int c = 0; c < 4; c++)
				out->to_object[i][r][c] = inst[i].inverse[r][c] * scale;
			out->to_object[i][r][3] -= o[r];
			for (int c = 0; c < 3; c++)
				largest = fmax(largest, fabs(inst[i].inverse[r][c]));
		}
		/* (A^-1)^T: row r of the normal matrix is column r of the inverse */
		double n_scale = unit_power_of_two(largest);
		for (int r = 0; r < 3; r++)
			for (int k = 0; k < 3; k++)
				out->to_world_normal[i][r][k] = inst[i].inverse[k][r] * n_scale;
	}
}

enum rs_status rs_pack_instances(const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                 const struct rs_pack_desc *pack, struct rs_packed_instances *out,
                                 struct rs_error *err)
{
	RS_ASSERT(scene && out);
	memset(out, 0, sizeof *out);
	static const struct rs_bvh_desc zero_bvh;
	if (!bvh)
		bvh = &zero_bvh;
	if (pack && pack->nodes == RS_PACK_NODES_WIDE4)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pack: instances need threaded nodes (compact or paper), not "
		                    "wide4");
	size_t ns = rs_scene_instance_count(scene), tris = rs_scene_triangle_count(scene);
	if (ns == 0)
		return rs_error_set(err, RS_ERR_INVALID, "pack: the scene has no instances");
	/* which triangles the instances bake (the rest go into the loose BLAS) */
	const struct rs_scene_instance *sinst = rs_scene_instances(scene);
	bool *covered = calloc(tris ? tris : 1, sizeof *covered);
	if (!covered)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for instances");
	size_t loose = tris;
	for (size_t i = 0; i < ns; i++)
		for (uint32_t t = 0; t < sinst[i].triangle_count; t++, loose--)
			covered[sinst[i].first_triangle + t] = true;
	size_t n = ns + (loose > 0);
	if (n >= RS_PACK_MAX_ITEMS) {
		free(covered);
		return rs_error_set(err, RS_ERR_LIMIT, "pack: %zu instances, over 2^24", n);
	}
	uint32_t protos = (uint32_t)rs_scene_prototype_count(scene);
	out->mesh_count = protos + (loose > 0);
	out->instance_count = (uint32_t)n;
	out->meshes = calloc(out->mesh_count, sizeof *out->meshes);
	out->to_object = malloc(n * sizeof *out->to_object);
	out->to_world_normal = malloc(n * sizeof *out->to_world_normal);
	out->mesh = malloc(n * sizeof *out->mesh);
	out->first_triangle = malloc(n * sizeof *out->first_triangle);
	out->loose_ids = loose > 0 ? malloc(loose * sizeof *out->loose_ids) : NULL;
	out->mesh_bounds = calloc(out->mesh_count, sizeof *out->mesh_bounds);
	out->mesh_scale = calloc(out->mesh_count, sizeof *out->mesh_scale);
	if (pack)
		out->pack = *pack;
	struct rs_scene_instance *inst = NULL;
	enum rs_status status = RS_OK;
	if (!out->meshes || !out->to_object || !out->to_world_normal || !out->mesh ||
	    !out->first_triangle || !out->mesh_bounds || !out->mesh_scale ||
	    (loose > 0 && !out->loose_ids))
		status = rs_error_set(err, RS_ERR_NO_MEMORY, "pack: out of memory for instances");
	if (status == RS_OK && !(inst = instance_list(scene, loose > 0, err)))
		status = RS_ERR_NO_MEMORY;
	if (status == RS_OK)
		status = pack_meshes(scene, bvh, pack, out, out->mesh_bounds, err);
	if (status == RS_OK && loose > 0)
		status = pack_loose(scene, covered, bvh, pack, out, &out->mesh_bounds[protos], err);
	if (status == RS_OK)
		status = pack_top(scene, inst, out->instance_count, bvh, pack, out->mesh_bounds,
		                  &out->top, &out->top_build_ms, &out->top_pack_ms, err);
	if (status == RS_OK) {
		out->build_ms += out->top_build_ms;
		set_transforms(out, inst);
	}
	free(covered);
	free(inst);
	if (status != RS_OK)
		rs_pack_instances_free(out);
	return status;
}

void rs_pack_instances_free(struct rs_packed_instances *packed)
{
	if (!packed)
		return;
	rs_pack_free(&packed->top);
	for (uint32_t k = 0; packed->meshes && k < packed->mesh_count; k++)
		rs_pack_free(&packed->meshes[k]);
	free(packed->meshes);
	free(packed->to_object);
	free(packed->to_world_normal);
	free(packed->mesh);
	free(packed->first_triangle);
	free(packed->loose_ids);
	free(packed->mesh_bounds);
	free(packed->mesh_scale);
	memset(packed, 0, sizeof *packed);
}

enum rs_status rs_pack_instances_update(struct rs_packed_instances *packed,
                                        const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                        struct rs_error *err)
{
	RS_ASSERT(packed && scene);
	static const struct rs_bvh_desc zero_bvh;
	if (!bvh)
		bvh = &zero_bvh;
	size_t ns = rs_scene_instance_count(scene), baked = 0;
	const struct rs_scene_instance *sinst = rs_scene_instances(scene);
	for (size_t i = 0; i < ns; i++)
		baked += sinst[i].triangle_count;
	bool loose = baked < rs_scene_triangle_count(scene);
	uint32_t protos = (uint32_t)rs_scene_prototype_count(scene);
	const char *what = NULL;
	if (!packed->mesh_bounds)
		what = "nothing was packed";
	else if (protos + loose != packed->mesh_count || loose != (packed->loose_ids != NULL))
		what = "the prototypes or the loose triangles differ";
	else if (ns + loose != packed->instance_count)
		what = "the instance count differs";
	for (size_t i = 0; !what && i < ns; i++)
		if (sinst[i].mesh != packed->mesh[i] ||
		    sinst[i].first_triangle != packed->first_triangle[i])
			what = "an instance's mesh or triangles differ";
	if (what)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "pack: instances_update: %s (only transforms may change; "
		                    "rs_pack_instances the scene)",
		                    what);
	struct rs_scene_instance *inst = instance_list(scene, loose, err);
	if (!inst)
		return RS_ERR_NO_MEMORY;
	struct rs_packed top = {0};
	double build_ms = 0.0, pack_ms = 0.0;
	enum rs_status status = pack_top(scene, inst, packed->instance_count, bvh, &packed->pack,
	                                 packed->mesh_bounds, &top, &build_ms, &pack_ms, err);
	if (status == RS_OK) {
		rs_pack_free(&packed->top);
		packed->top = top;
		packed->build_ms += build_ms - packed->top_build_ms;
		packed->top_build_ms = build_ms;
		packed->top_pack_ms = pack_ms;
		set_transforms(packed, inst);
	}
	free(inst);
	return status;
}

static size_t texture_bytes(const struct rs_texture *t)
{
	return (size_t)t->width * t->height * 16u;
}

size_t rs_pack_bytes(const struct rs_packed *packed)
{
	return texture_bytes(&packed->nodes) + texture_bytes(&packed->triangles) +
	       texture_bytes(&packed->normals) + texture_bytes(&packed->materials);
}

size_t rs_pack_instances_bytes(const struct rs_packed_instances *packed)
{
	size_t bytes = rs_pack_bytes(&packed->top) + (size_t)packed->instance_count * 6u * 16u;
	if (packed->loose_ids) /* the loose ids a GPU would need beside their BLAS */
		bytes += (size_t)packed->meshes[packed->mesh_count - 1].triangle_count * 4u;
	for (uint32_t k = 0; k < packed->mesh_count; k++)
		bytes += rs_pack_bytes(&packed->meshes[k]);
	return bytes;
}
