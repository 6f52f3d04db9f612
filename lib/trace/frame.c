/* The frame description (Part 3 of rs_trace.h): every number of a frame resolved once,
 * for the CPU tracer and for the GPU backends that hand the same values to their kernels.
 * Semantics: docs/tracer.md. */
#include <string.h>

#include "trace_internal.h"

enum rs_status rs_trace_frame_init(const struct rs_scene *scene, const struct rs_packed *packed,
                                   const struct rs_trace_desc *desc, struct rs_trace_frame *out,
                                   struct rs_error *err)
{
	static const struct rs_trace_desc zero_desc;
	if (!desc)
		desc = &zero_desc;
	RS_ASSERT(scene && packed);
	size_t tris = rs_scene_triangle_count(scene);
	const struct rs_packed_two_level *two = desc->two_level;
	if (two && (packed->nodes.texels != two->all.nodes.texels || two->scene_triangles != tris))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "trace: the two-level packing is not this scene's or not the "
		                    "packed textures given");
	if (!two && packed->triangle_count != tris)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "trace: packed arrays hold %u triangles, the scene %zu",
		                    packed->triangle_count, tris);
	if (tris > 0 && packed->node_count == 0)
		return rs_error_set(err, RS_ERR_INVALID, "trace: packed arrays have no BVH nodes");
	/* rs_pack_texel() addresses items linearly, which is the kernels' 2D layout only for
	 * textures sized exactly as rs_pack_layout() sizes them. */
	enum rs_status st = rs_pack_check(packed, err);
	if (st != RS_OK)
		return st;
	if (desc->triangle_test != RS_TRIANGLE_MOLLER_TRUMBORE &&
	    desc->triangle_test != RS_TRIANGLE_WATERTIGHT)
		return rs_error_set(err, RS_ERR_INVALID, "trace: unknown triangle test %d",
		                    (int)desc->triangle_test);
	if (desc->passes > RS_TRACE_MAX_PASSES)
		return rs_error_set(err, RS_ERR_INVALID, "trace: %u passes (at most %u)",
		                    desc->passes, RS_TRACE_MAX_PASSES);
	size_t scene_lights = rs_scene_light_count(scene);
	if (desc->lights > scene_lights)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "trace: %u lights asked, the scene has %zu", desc->lights,
		                    scene_lights);
	if (!isfinite(desc->ray_epsilon) || desc->ray_epsilon < 0.0)
		return rs_error_set(err, RS_ERR_INVALID, "trace: ray epsilon %g is not >= 0",
		                    desc->ray_epsilon);
	if (desc->intersector && (!desc->intersector->closest || !desc->intersector->occluded))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "trace: the intersector lacks a closest or occluded query");

	memset(out, 0, sizeof *out);
	out->packed = packed;
	out->test = desc->triangle_test;
	out->passes = desc->passes ? desc->passes : 2u;
	out->light_count = desc->lights ? desc->lights : (uint32_t)scene_lights;
	out->lights = rs_scene_lights(scene);
	out->ambient = rs_scene_ambient(scene);
	out->has_geometry = tris > 0;
	out->intersector = desc->intersector;
	out->two_level = two;
	out->unshadowed = desc->unshadowed;
	out->rules = (struct rs_trace_rules){.box_k = RS_TRACE_BOX_K,
	                                     .box_k_fp32 = RS_TRACE_BOX_K_FP32,
	                                     .grid_box_e_fp32 = RS_TRACE_GRID_BOX_E_FP32,
	                                     .parallel_eps = RS_TRACE_PARALLEL_EPS,
	                                     .spawn_pull_height = RS_TRACE_SPAWN_PULL_HEIGHT,
	                                     .spawn_pull = RS_TRACE_SPAWN_PULL};
	rs_scene_environment(scene, &out->env);
	/* rs_scene_environment() resolves every default; a half-size the scene could not
	 * give (none, or not finite) is 1, as rs_trace_environment() takes it. */
	if (!(out->env.half_size > 0.0) || !isfinite(out->env.half_size))
		out->env.half_size = 1.0;

	/* R5: the offset scales with the hit triangle's coordinates in the packed frame. */
	out->spawn_scale = desc->ray_epsilon > 0.0 ? desc->ray_epsilon : RS_TRACE_SPAWN_SCALE;
	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	double half = 0.0, r2 = 0.0;
	for (int a = 0; a < 3; ++a)
		if (b.hi[a] >= b.lo[a]) {
			half = fmax(half, 0.5 * (b.hi[a] - b.lo[a]));
			r2 += 0.25 * (b.hi[a] - b.lo[a]) * (b.hi[a] - b.lo[a]);
		}
	out->spawn_floor = fmax(half * RS_TRACE_SPAWN_FLOOR_SHARE, RS_TRACE_SPAWN_FLOOR_MIN);
	out->bounds_radius = sqrt(r2);
	/* R1: everything is traced in the packed frame. */
	for (int a = 0; a < 3; ++a) {
		out->origin[a] = packed->origin[a];
		out->env.center[a] -= packed->origin[a];
		out->bounds_center[a] =
		    b.hi[a] >= b.lo[a] ? 0.5 * (b.lo[a] + b.hi[a]) - packed->origin[a] : 0.0;
	}
	return RS_OK;
}

void rs_trace_frame_light(const struct rs_trace_frame *frame, uint32_t i, double out_position[3])
{
	RS_ASSERT(frame && out_position && i < frame->light_count);
	for (int a = 0; a < 3; ++a)
		out_position[a] = frame->lights[i].position[a] - frame->origin[a];
}

double rs_trace_frame_reach(const struct rs_trace_frame *frame, const double eye[3])
{
	RS_ASSERT(frame && eye);
	if (!frame->has_geometry)
		return 0.0;
	double reach = 0.0;
	for (int a = 0; a < 3; ++a) {
		reach = fmax(reach, fabs(frame->bounds_center[a]) + frame->bounds_radius);
		reach = fmax(reach, fabs(frame->env.center[a]) + frame->env.half_size);
		reach = fmax(reach, fabs(eye[a]));
	}
	for (uint32_t i = 0; i < frame->light_count; ++i) {
		double p[3];
		rs_trace_frame_light(frame, i, p);
		for (int a = 0; a < 3; ++a)
			reach = fmax(reach, fabs(p[a]));
	}
	return reach;
}
