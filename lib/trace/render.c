/* rs_trace_render() and rs_trace_ray_path(): descriptor validation, the per-frame
 * constants, and the pixel loop with its statistics. Semantics: docs/tracer.md. */
#include <string.h>

#include "render_internal.h"

enum rs_status rs_trace_frame_init(const struct rs_scene *scene, const struct rs_packed *packed,
                                   const struct rs_trace_desc *desc, struct rs_trace_frame *out,
                                   struct rs_error *err)
{
	static const struct rs_trace_desc zero_desc;
	if (!desc)
		desc = &zero_desc;
	RS_ASSERT(scene && packed);
	size_t tris = rs_scene_triangle_count(scene);
	if (packed->triangle_count != tris)
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
	rs_scene_environment(scene, &out->env);

	/* R5: the offset scales with the hit triangle's coordinates in the packed frame. */
	out->spawn_scale = desc->ray_epsilon > 0.0 ? desc->ray_epsilon : RS_TRACE_SPAWN_SCALE;
	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	double half = 0.0;
	for (int a = 0; a < 3; ++a)
		if (b.hi[a] >= b.lo[a])
			half = fmax(half, 0.5 * (b.hi[a] - b.lo[a]));
	out->spawn_floor = fmax(half / 16.0, 0x1p-64);
	/* R1: everything is traced in the packed frame. */
	for (int a = 0; a < 3; ++a) {
		out->origin[a] = packed->origin[a];
		out->env.center[a] -= packed->origin[a];
	}
	return RS_OK;
}

enum rs_status rs_trace_ray_path(const struct rs_scene *scene, const struct rs_packed *packed,
                                 const struct rs_trace_desc *desc, const struct rs_ray *primary,
                                 struct rs_trace_path *out_path,
                                 struct rs_trace_segment *out_segments, struct rs_error *err)
{
	RS_ASSERT(primary && out_path);
	struct rs_trace_frame frame;
	enum rs_status st = rs_trace_frame_init(scene, packed, desc, &frame, err);
	if (st != RS_OK)
		return st;
	struct rs_ray ray = *primary;
	for (int a = 0; a < 3; ++a)
		if (!isfinite(ray.origin[a]) || !isfinite(ray.dir[a]))
			return rs_error_set(err, RS_ERR_INVALID, "trace: ray is not finite");
	/* Unit directions are kept bit for bit, so a camera ray traced here takes exactly the
	 * path rs_trace_render() gives it (renormalising can change the last bit). */
	double len2 = rs_v3_dot(ray.dir, ray.dir);
	if (fabs(len2 - 1.0) > 1e-12 && rs_v3_normalize(ray.dir) == 0.0)
		return rs_error_set(err, RS_ERR_INVALID, "trace: ray direction is zero");
	if (!(ray.tmax > ray.tmin) || isnan(ray.tmin))
		return rs_error_set(err, RS_ERR_INVALID, "trace: ray interval is empty");
	for (int a = 0; a < 3; ++a)
		ray.origin[a] -= frame.origin[a];
	rs_trace_path_run(&frame, &ray, out_path, out_segments);
	return RS_OK;
}

enum rs_status rs_trace_render(const struct rs_scene *scene, const struct rs_packed *packed,
                               const struct rs_trace_desc *desc, float *out_rgb, float *out_depth,
                               struct rs_trace_stats *out_stats, struct rs_error *err)
{
	static const struct rs_trace_desc zero_desc;
	if (!desc)
		desc = &zero_desc;
	struct rs_trace_frame frame;
	enum rs_status st = rs_trace_frame_init(scene, packed, desc, &frame, err);
	if (st != RS_OK)
		return st;

	struct rs_camera cam;
	rs_camera_resolve(desc->camera ? desc->camera : rs_scene_camera(scene), &cam);
	uint32_t width = desc->width, height = desc->height;
	if (width == 0 || height == 0) {
		width = cam.width;
		height = cam.height;
	}
	if (width > 65536 || height > 65536)
		return rs_error_set(err, RS_ERR_LIMIT, "trace: image %ux%u is too large", width,
		                    height);
	uint32_t row_begin = desc->row_begin, row_end = desc->row_end;
	if (row_begin == 0 && row_end == 0)
		row_end = height;
	if (row_begin > row_end || row_end > height)
		return rs_error_set(err, RS_ERR_INVALID, "trace: rows [%u, %u) outside 0..%u",
		                    row_begin, row_end, height);

	struct rs_trace_stats stats = {0};
	for (uint32_t y = row_begin; y < row_end; ++y) {
		for (uint32_t x = 0; x < width; ++x) {
			struct rs_ray ray;
			struct rs_trace_path path;
			rs_trace_camera_ray(&cam, width, height, x + 0.5, y + 0.5, &ray);
			for (int a = 0; a < 3; ++a)
				ray.origin[a] -= frame.origin[a];
			rs_trace_path_run(&frame, &ray, &path, NULL);
			size_t i = (size_t)y * width + x;
			if (out_rgb)
				for (int c = 0; c < 3; ++c)
					out_rgb[i * 3 + c] = (float)path.rgb[c];
			if (out_depth)
				out_depth[i] = (float)path.depth;
			stats.rays += path.segments;
			stats.shadow_rays += path.shadow_rays;
			stats.box_tests += path.counters.box_tests;
			stats.triangle_tests += path.counters.triangle_tests;
		}
	}
	stats.pixels = (uint64_t)(row_end - row_begin) * width;
	if (stats.pixels > 0) {
		stats.box_per_pixel = (double)stats.box_tests / (double)stats.pixels;
		stats.triangle_per_pixel = (double)stats.triangle_tests / (double)stats.pixels;
		stats.total_per_pixel = stats.box_per_pixel + stats.triangle_per_pixel;
	}
	if (out_stats)
		*out_stats = stats;
	return RS_OK;
}
