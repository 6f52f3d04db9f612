/* Environment kernel of the reference renderer: rays that leave the scene take the colour
 * of the environment cube where they cross it. Using the exit point (not just the
 * direction, as a classic environment map would) is what removes parallax. */
#include "trace_internal.h"

/* Grid coordinate of a face position in [0, 1]: cell index and whether it is on a line.
 * Lines are centred on cell borders (the face edges included), line_width of a cell wide. */
static void grid_cell(double pos, uint32_t grid, double line_width, uint32_t *cell, bool *line)
{
	double g = pos * (double)grid;
	double f = floor(g);
	double frac = g - f;
	uint32_t c = f <= 0.0 ? 0u : (uint32_t)f;
	*cell = c >= grid ? grid - 1u : c;
	if (fmin(frac, 1.0 - frac) < 0.5 * line_width)
		*line = true;
}

void rs_trace_environment(const struct rs_environment *env, const double origin[3],
                          const double dir[3], struct rs_env_hit *out_hit, double out_rgb[3])
{
	uint32_t grid = env->grid ? env->grid : 16u;
	double line_width = env->line_width > 0.0f ? env->line_width : 0.06;
	double line_scale = env->line_scale > 0.0f ? env->line_scale : 0.25;
	double h = env->half_size > 0.0 && isfinite(env->half_size) ? env->half_size : 1.0;

	/* Exit through the nearest far slab plane. Ties (edges, corners) go to the lowest
	 * axis. A ray starting outside the cube still gets the nearest far plane's point,
	 * clamped onto the face below. */
	int axis = -1;
	double best = INFINITY;
	for (int a = 0; a < 3; ++a) {
		if (!(dir[a] != 0.0) || !isfinite(dir[a]))
			continue;
		double plane = env->center[a] + (dir[a] > 0.0 ? h : -h);
		double t = (plane - origin[a]) / dir[a];
		if (t < best) {
			best = t;
			axis = a;
		}
	}
	struct rs_env_hit hit = {0};
	if (axis < 0 || !isfinite(best)) {
		axis = 0;
		for (int a = 0; a < 3; ++a)
			hit.point[a] = env->center[a];
		hit.point[0] += h;
		hit.face = 0;
	} else {
		rs_v3_madd(origin, best, dir, hit.point);
		hit.point[axis] = env->center[axis] + (dir[axis] > 0.0 ? h : -h);
		hit.face = 2u * (uint32_t)axis + (dir[axis] > 0.0 ? 0u : 1u);
	}
	int as = (axis + 1) % 3, at = (axis + 2) % 3;
	hit.s = fmin(fmax(0.5 * ((hit.point[as] - env->center[as]) / h + 1.0), 0.0), 1.0);
	hit.t = fmin(fmax(0.5 * ((hit.point[at] - env->center[at]) / h + 1.0), 0.0), 1.0);
	hit.line = false;
	grid_cell(hit.s, grid, line_width, &hit.cell_s, &hit.line);
	grid_cell(hit.t, grid, line_width, &hit.cell_t, &hit.line);

	double scale = hit.line ? line_scale : 1.0;
	for (int c = 0; c < 3; ++c)
		out_rgb[c] = (double)env->face_color[hit.face][c] * scale;
	if (out_hit)
		*out_hit = hit;
}
