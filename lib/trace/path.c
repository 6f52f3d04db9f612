/* The pass loop of the reference renderer: one path per pixel, one segment per pass, in
 * the order the GLES kernel chain runs (intersection -> environment -> shading -> next
 * ray). colour += throughput * local; throughput *= weight of the chosen continuation. */
#include <string.h>

#include "intersect_internal.h"
#include "trace_internal.h"

void rs_trace_path_run(const struct rs_trace_frame *frame, const struct rs_ray *primary,
                       struct rs_trace_path *out, struct rs_trace_segment *segments)
{
	memset(out, 0, sizeof *out);
	out->depth = INFINITY;
	out->state = RS_RAY_ACTIVE;
	struct rs_ray ray = *primary;
	double throughput = 1.0;

	for (uint32_t pass = 0; pass < frame->passes; ++pass) {
		struct rs_hit hit = {.t = INFINITY, .slot = RS_NO_SLOT, .triangle = RS_NO_SLOT};
		bool found = frame->has_geometry &&
		             rs_trace_frame_closest(frame, &ray, &hit, &out->counters);
		out->segments++;
		struct rs_trace_segment seg = {.ray = ray, .throughput = throughput};
		for (int a = 0; a < 3; ++a)
			seg.ray.origin[a] += frame->origin[a]; /* reported in world coordinates */
		if (!found) {
			/* state -1; the environment kernel resolves it at once to -2 */
			double env[3];
			rs_trace_environment(&frame->env, ray.origin, ray.dir, NULL, env);
			for (int c = 0; c < 3; ++c)
				out->rgb[c] += throughput * env[c];
			seg.hit = (struct rs_hit){
			    .t = INFINITY, .slot = RS_NO_SLOT, .triangle = RS_NO_SLOT};
			seg.state = out->state = RS_RAY_ENVIRONMENT;
			if (segments)
				segments[pass] = seg;
			break;
		}
		if (pass == 0)
			out->depth = hit.t;
		struct rs_surface surf;
		rs_trace_surface(frame, &ray, &hit, &surf);
		rs_trace_shade(frame, &ray, &hit, &surf, throughput, out->rgb, out);

		struct rs_ray next;
		double weight;
		seg.hit = hit;
		seg.state = out->state =
		    rs_trace_next_ray(frame, &ray, &hit, &surf, &next, &weight);
		if (segments)
			segments[pass] = seg;
		if (seg.state != RS_RAY_ACTIVE)
			break;
		throughput *= weight;
		ray = next;
	}
}
