/* What every backend starts from: the scene's BVH, built with the chosen builder and packed
 * into the textures the kernels (and the CPU reference) read, and the reference tracer's
 * descriptor from which each resolves its frame (rs_trace_frame_init()). */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render_internal.h"

enum rs_status rs_render_accel_build(const struct rs_scene *scene, const struct rs_bvh_desc *bvh,
                                     const struct rs_pack_desc *pack, struct rs_render_accel *out,
                                     struct rs_error *err)
{
	RS_ASSERT(scene && out);
	static const struct rs_bvh_desc zero_bvh;
	if (!bvh)
		bvh = &zero_bvh;
	memset(out, 0, sizeof *out);
	size_t tris = rs_scene_triangle_count(scene);
	size_t cap = rs_bvh_node_bound(bvh, tris);
	out->nodes = malloc((cap ? cap : 1) * sizeof *out->nodes);
	out->triangle_order = malloc((tris ? tris : 1) * sizeof *out->triangle_order);
	if (!out->nodes || !out->triangle_order) {
		rs_render_accel_free(out);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "render: out of memory for the BVH");
	}
	double t0 = rs_now_ms();
	enum rs_status status = rs_bvh_build(
	    bvh, rs_scene_positions(scene), rs_scene_vertex_count(scene), rs_scene_indices(scene),
	    tris, out->nodes, cap, out->triangle_order, &out->node_count, err);
	out->build_ms = rs_now_ms() - t0;
	if (status == RS_OK)
		status = rs_pack_layout(pack, out->node_count, tris, rs_scene_material_count(scene),
		                        &out->packed, err);
	if (status == RS_OK)
		status = rs_pack_alloc(&out->packed, err);
	double t1 = rs_now_ms();
	if (status == RS_OK)
		status = rs_pack_scene(scene, out->nodes, out->node_count, out->triangle_order,
		                       &out->packed, err);
	out->pack_ms = rs_now_ms() - t1;
	if (status == RS_OK) {
		struct rs_bvh_desc resolved;
		struct rs_bvh_stats bs;
		rs_bvh_desc_resolve(bvh, &resolved);
		rs_bvh_stats(out->nodes, out->node_count, resolved.traversal_cost, &bs);
		out->build_sah = bs.sah_cost;
	}
	if (status != RS_OK)
		rs_render_accel_free(out);
	return status;
}

enum rs_status rs_render_accel_build_two_level(const struct rs_scene *scene,
                                               const struct rs_bvh_desc *bvh,
                                               const struct rs_pack_desc *pack,
                                               struct rs_render_accel *out, struct rs_error *err)
{
	RS_ASSERT(scene && out);
	memset(out, 0, sizeof *out);
	struct rs_packed_instances pi;
	double t0 = rs_now_ms();
	enum rs_status status = rs_pack_instances(scene, bvh, pack, &pi, err);
	if (status != RS_OK)
		return status;
	double t1 = rs_now_ms();
	status = rs_pack_two_level(scene, &pi, &out->two_level, err);
	out->build_ms = pi.build_ms;
	/* rs_pack_instances() builds and packs each tree: what is not building is packing */
	out->pack_ms = (t1 - t0 - pi.build_ms) + (rs_now_ms() - t1);
	out->instances = pi;
	if (status != RS_OK) {
		rs_render_accel_free(out);
		return status;
	}
	out->packed = out->two_level.all;
	return RS_OK;
}

enum rs_status rs_render_accel_update_instances(struct rs_render_accel *accel,
                                                const struct rs_scene *scene,
                                                const struct rs_bvh_desc *bvh, struct rs_error *err)
{
	RS_ASSERT(accel && scene);
	if (!accel->two_level.instance_count)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "render: instance update of a scene not in two levels");
	enum rs_status st = rs_pack_instances_update(&accel->instances, scene, bvh, err);
	double t0 = rs_now_ms();
	if (st == RS_OK)
		st = rs_pack_two_level_update(scene, &accel->instances, &accel->two_level, err);
	accel->tlas_build_ms = accel->instances.top_build_ms;
	accel->pack_ms = accel->instances.top_pack_ms + (rs_now_ms() - t0);
	/* the TLAS frame moved with the instances */
	accel->packed = accel->two_level.all;
	return st;
}

enum rs_status rs_render_two_level(const struct rs_render_desc *desc, const struct rs_scene *scene,
                                   bool *out_two_level, struct rs_error *err)
{
	RS_ASSERT(desc && scene && out_two_level);
	*out_two_level = false;
	if (desc->instances == RS_INSTANCES_FLATTEN)
		return RS_OK;
	if (desc->instances != RS_INSTANCES_AUTO && desc->instances != RS_INSTANCES_TWO_LEVEL)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown instances mode %d",
		                    (int)desc->instances);
	bool forced = desc->instances == RS_INSTANCES_TWO_LEVEL;
	const char *why = NULL;
	if (rs_scene_instance_count(scene) == 0)
		why = "the scene has no instances";
	else if (desc->pack.nodes == RS_PACK_NODES_WIDE4)
		why = "wide4 nodes are not threaded (use compact or paper nodes)";
	if (why && forced)
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "render: instances two-level: %s",
		                    why);
	*out_two_level = why == NULL;
	return RS_OK;
}

void rs_render_accel_free(struct rs_render_accel *accel)
{
	if (!accel)
		return;
	if (accel->two_level.instance_count) {
		/* packed is two_level.all: freed once, below */
		memset(&accel->packed, 0, sizeof accel->packed);
		rs_pack_two_level_free(&accel->two_level);
	}
	if (accel->instances.instance_count)
		rs_pack_instances_free(&accel->instances);
	free(accel->nodes);
	free(accel->triangle_order);
	rs_pack_free(&accel->packed);
	memset(accel, 0, sizeof *accel);
}

struct rs_trace_desc rs_render_trace_desc(const struct rs_render_desc *desc)
{
	RS_ASSERT(desc);
	return (struct rs_trace_desc){.width = desc->width,
	                              .height = desc->height,
	                              .passes = desc->passes,
	                              .lights = desc->lights,
	                              .triangle_test = desc->triangle_test,
	                              .ray_epsilon = desc->ray_epsilon,
	                              .unshadowed = desc->shadows == RS_SHADOW_NONE};
}

struct rs_bvh_desc rs_render_bvh_desc(const struct rs_render_desc *desc)
{
	RS_ASSERT(desc);
	struct rs_bvh_desc bvh = desc->bvh;
	/* The build shares the renderer's threads (the tree is the same for any count, so
	 * images and hit numbers do not change); 0 -> the machine's cores, as for rendering. */
	if (bvh.threads == 0) {
		long cores = sysconf(_SC_NPROCESSORS_ONLN);
		bvh.threads = desc->threads ? desc->threads : cores > 0 ? (uint32_t)cores : 1u;
		if (bvh.threads > RS_BVH_MAX_THREADS)
			bvh.threads = RS_BVH_MAX_THREADS;
	}
	return bvh;
}
