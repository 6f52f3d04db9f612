/* Per-frame vertex updates: the topology rule (what may not change between frames: counts,
 * indices, materials; lights, ambient and a bounds-derived environment follow the new scene,
 * as every backend reads them from it again) and the refit-or-rebuild step every backend runs
 * before it repacks and uploads. The rule on when to rebuild is measured in docs/bvh.md ("Refit").
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

static bool same_materials(const struct rs_material *a, const struct rs_material *b, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (memcmp(a[i].diffuse, b[i].diffuse, sizeof a[i].diffuse) != 0 ||
		    a[i].specular != b[i].specular || a[i].shininess != b[i].shininess ||
		    a[i].reflectance != b[i].reflectance ||
		    a[i].transmittance != b[i].transmittance || a[i].ior != b[i].ior ||
		    a[i].flags != b[i].flags)
			return false;
	return true;
}

enum rs_status rs_render_scene_same_topology(const struct rs_scene *current,
                                             const struct rs_scene *next, struct rs_error *err)
{
	RS_ASSERT(current && next);
	const char *what = NULL;
	size_t tris = rs_scene_triangle_count(current);
	size_t mats = rs_scene_material_count(current);
	if (rs_scene_triangle_count(next) != tris)
		what = "the triangle count";
	else if (rs_scene_vertex_count(next) != rs_scene_vertex_count(current))
		what = "the vertex count";
	else if (memcmp(rs_scene_indices(next), rs_scene_indices(current),
	                3 * tris * sizeof(uint32_t)) != 0)
		what = "the triangles' vertex indices";
	else if (memcmp(rs_scene_triangle_materials(next), rs_scene_triangle_materials(current),
	                tris * sizeof(uint32_t)) != 0)
		what = "the triangles' materials";
	else if (rs_scene_material_count(next) != mats ||
	         !same_materials(rs_scene_materials(next), rs_scene_materials(current), mats))
		what = "the materials";
	if (what)
		return rs_error_set(
		    err, RS_ERR_INVALID,
		    "render: update_vertices: %s changed (only positions and normals "
		    "may; set_scene the new scene)",
		    what);
	return RS_OK;
}

/* A copy of the tree (refit works in place, and `accel` stays as the GPU holds it). */
static enum rs_status copy_tree(const struct rs_render_accel *accel, size_t tris,
                                struct rs_render_accel *out, struct rs_error *err)
{
	out->nodes = malloc((accel->node_count ? accel->node_count : 1) * sizeof *out->nodes);
	out->triangle_order = malloc((tris ? tris : 1) * sizeof *out->triangle_order);
	if (!out->nodes || !out->triangle_order)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "render: out of memory for the BVH");
	memcpy(out->nodes, accel->nodes, accel->node_count * sizeof *out->nodes);
	memcpy(out->triangle_order, accel->triangle_order, tris * sizeof *out->triangle_order);
	out->node_count = accel->node_count;
	return RS_OK;
}

enum rs_status rs_render_accel_update(const struct rs_render_accel *accel,
                                      const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                      const struct rs_pack_desc *pack, double rebuild_ratio,
                                      struct rs_render_accel *out, struct rs_error *err)
{
	RS_ASSERT(accel && scene && out);
	static const struct rs_bvh_desc zero_bvh;
	if (!bvh)
		bvh = &zero_bvh;
	struct rs_bvh_desc resolved;
	rs_bvh_desc_resolve(bvh, &resolved);
	if (rebuild_ratio == 0.0)
		rebuild_ratio = RS_BVH_REBUILD_RATIO;
	memset(out, 0, sizeof *out);
	if (accel->two_level.instance_count) {
		/* Two levels have no tree over the scene's triangles to refit: both levels are
		 * built again (the same layout when the scene's instances and meshes are). */
		enum rs_status st = rs_render_accel_build_two_level(scene, bvh, pack, out, err);
		out->rebuilt = true;
		return st;
	}
	size_t tris = rs_scene_triangle_count(scene);
	double t0 = rs_now_ms();
	enum rs_status st = copy_tree(accel, tris, out, err);
	if (st == RS_OK)
		st = rs_bvh_refit(out->nodes, out->node_count, rs_scene_positions(scene),
		                  rs_scene_vertex_count(scene), rs_scene_indices(scene),
		                  out->triangle_order, tris, err);
	if (st != RS_OK) {
		rs_render_accel_free(out);
		return st;
	}
	struct rs_bvh_stats bs;
	rs_bvh_stats(out->nodes, out->node_count, resolved.traversal_cost, &bs);
	out->refit_ms = rs_now_ms() - t0;
	out->build_sah = accel->build_sah;
	out->sah_ratio = accel->build_sah > 0.0 ? bs.sah_cost / accel->build_sah : 1.0;
	/* NaN never rebuilds by accident: the comparison is false for it (and the cost of a
	 * finite tree is finite). */
	if (out->sah_ratio > rebuild_ratio) {
		double refit_ms = out->refit_ms, ratio = out->sah_ratio;
		rs_render_accel_free(out);
		st = rs_render_accel_build(scene, bvh, pack, out, err);
		out->rebuilt = st == RS_OK;
		out->refit_ms = refit_ms; /* spent before deciding */
		out->sah_ratio = ratio;
		return st;
	}
	st = rs_pack_layout(pack, out->node_count, tris, rs_scene_material_count(scene),
	                    &out->packed, err);
	if (st == RS_OK)
		st = rs_pack_alloc(&out->packed, err);
	double t1 = rs_now_ms();
	if (st == RS_OK)
		st = rs_pack_scene(scene, out->nodes, out->node_count, out->triangle_order,
		                   &out->packed, err);
	out->pack_ms = rs_now_ms() - t1;
	if (st != RS_OK)
		rs_render_accel_free(out);
	return st;
}
