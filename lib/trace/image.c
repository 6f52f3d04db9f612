/* rs_trace_render() and rs_trace_ray_path(): the pixel loop with its statistics over the
 * frame description (frame.c). Semantics: docs/tracer.md. */
#include <string.h>

#include "trace_internal.h"

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

	struct rs_trace_view view;
	rs_trace_view_init(desc->camera ? desc->camera : rs_scene_camera(scene), frame.origin,
	                   desc->width, desc->height, &view);
	uint32_t width = view.width, height = view.height;
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
			rs_trace_view_ray(&view, x + 0.5, y + 0.5, &ray);
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
