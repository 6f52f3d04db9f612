/* rs_trace: the environment cube lookup (exit point, face colours, grid lines, no parallax). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_trace.h"

/* Cube of half-size 10 around (1, 2, 3), a 10x10 grid (cells 2 units wide), lines 0.1 of a
 * cell (0.2 units), drawn at half brightness. Face f has colour (0.1 f + 0.1, 0.5, 1 - 0.1 f). */
static struct rs_environment test_env(void)
{
	struct rs_environment env = {.center = {1, 2, 3},
	                             .half_size = 10,
	                             .grid = 10,
	                             .line_width = 0.1f,
	                             .line_scale = 0.5f};
	for (int f = 0; f < 6; ++f) {
		env.face_color[f][0] = 0.1f * (float)f + 0.1f;
		env.face_color[f][1] = 0.5f;
		env.face_color[f][2] = 1.0f - 0.1f * (float)f;
	}
	return env;
}

static void each_axis_direction_picks_its_face(void **state)
{
	struct rs_environment env = test_env();
	/* slightly off the axes so that no ray lands on a grid line (cell centres at odd
	 * offsets from the centre) */
	const double dirs[6][3] = {{1, 0.1, 0.1},  {-1, 0.1, 0.1}, {0.1, 1, 0.1},
	                           {0.1, -1, 0.1}, {0.1, 0.1, 1},  {0.1, 0.1, -1}};
	for (uint32_t f = 0; f < 6; ++f) {
		struct rs_env_hit hit;
		double rgb[3];
		rs_trace_environment(&env, env.center, dirs[f], &hit, rgb);
		assert_int_equal(hit.face, f);
		assert_false(hit.line);
		for (int c = 0; c < 3; ++c)
			assert_true(rgb[c] == (double)env.face_color[f][c]);
	}
}

static void exit_point_lies_on_the_face(void **state)
{
	struct rs_environment env = test_env();
	double origin[3] = {3, 4, 5}, dir[3] = {0.2, -0.3, 0.9};
	struct rs_env_hit hit;
	double rgb[3];
	rs_trace_environment(&env, origin, dir, &hit, rgb);
	/* +z plane at 13: t = 8 / 0.9; x = 3 + 0.2 t, y = 4 - 0.3 t */
	double t = 8.0 / 0.9;
	assert_int_equal(hit.face, 4);
	/* tolerance: a few ulps of coordinates of magnitude ~10 */
	assert_true(fabs(hit.point[0] - (3 + 0.2 * t)) < 1e-12);
	assert_true(fabs(hit.point[1] - (4 - 0.3 * t)) < 1e-12);
	assert_true(hit.point[2] == 13.0);
	/* face +z: s runs along x, t along y, both from the cube's low corner */
	assert_true(fabs(hit.s - ((3 + 0.2 * t) - 1 + 10) / 20) < 1e-12);
	assert_true(fabs(hit.t - ((4 - 0.3 * t) - 2 + 10) / 20) < 1e-12);
}

static void grid_lines_darken_by_line_scale(void **state)
{
	struct rs_environment env = test_env();
	double origin[3] = {1, 2, 3};
	struct rs_env_hit hit;
	double rgb[3];
	/* towards (x = 1 + 2.05, z = 13): 0.05 units from the cell border at x = 3 (the line
	 * is 0.1 units either side), y at a cell centre */
	double on_line[3] = {2.05, 1.0, 10.0};
	rs_trace_environment(&env, origin, on_line, &hit, rgb);
	assert_int_equal(hit.face, 4);
	assert_true(hit.line);
	for (int c = 0; c < 3; ++c)
		assert_true(fabs(rgb[c] - 0.5 * env.face_color[4][c]) < 1e-7);
	/* 0.15 units from the border: outside the line */
	double off_line[3] = {2.15, 1.0, 10.0};
	rs_trace_environment(&env, origin, off_line, &hit, rgb);
	assert_false(hit.line);
	assert_true(rgb[0] == (double)env.face_color[4][0]);
}

static void face_edges_are_lines_and_cells_stay_in_range(void **state)
{
	struct rs_environment env = test_env();
	double origin[3] = {1, 2, 3};
	struct rs_env_hit hit;
	double rgb[3];
	double corner[3] = {1, 1, 1}; /* exactly through a cube corner */
	rs_trace_environment(&env, origin, corner, &hit, rgb);
	assert_int_equal(hit.face, 0); /* ties go to the lowest axis */
	assert_true(hit.line);
	assert_int_equal(hit.cell_s, env.grid - 1);
	assert_int_equal(hit.cell_t, env.grid - 1);
}

static void parallel_rays_from_different_origins_hit_different_cells(void **state)
{
	/* a direction-only environment map would give both rays the same texel */
	struct rs_environment env = test_env();
	double dir[3] = {0.1, 0.05, 1.0};
	double a[3] = {1, 2, 3}, b[3] = {6, 2, 3};
	struct rs_env_hit ha, hb;
	double ca[3], cb[3];
	rs_trace_environment(&env, a, dir, &ha, ca);
	rs_trace_environment(&env, b, dir, &hb, cb);
	assert_int_equal(ha.face, hb.face);
	assert_int_not_equal(ha.cell_s, hb.cell_s);
	/* both exits are 10 units up, so x differs by exactly the origins' 5 units */
	assert_true(fabs((hb.point[0] - ha.point[0]) - 5.0) < 1e-12);
}

static void zero_direction_gets_a_defined_colour(void **state)
{
	struct rs_environment env = test_env();
	double zero[3] = {0, 0, 0};
	struct rs_env_hit hit;
	double rgb[3];
	rs_trace_environment(&env, env.center, zero, &hit, rgb);
	assert_int_equal(hit.face, 0);
	for (int c = 0; c < 3; ++c)
		assert_true(isfinite(rgb[c]));
}

static void origin_outside_the_cube_stays_finite(void **state)
{
	struct rs_environment env = test_env();
	double origin[3] = {100, -50, 70}, dir[3] = {1, 1, 1};
	struct rs_env_hit hit;
	double rgb[3];
	rs_trace_environment(&env, origin, dir, &hit, rgb);
	assert_true(hit.s >= 0.0 && hit.s <= 1.0 && hit.t >= 0.0 && hit.t <= 1.0);
	assert_true(hit.cell_s < env.grid && hit.cell_t < env.grid);
	for (int c = 0; c < 3; ++c)
		assert_true(isfinite(rgb[c]));
}

static void zero_grid_fields_take_the_defaults(void **state)
{
	/* grid 16, line width 0.06: 0.02 of a cell from a border is on a line */
	struct rs_environment env = {.half_size = 8};
	env.face_color[4][0] = 1.0f;
	double origin[3] = {0, 0, 0};
	double dir[3] = {0.02, 0.5, 8.0}; /* x = 0.02 units = 0.02 cells from the border at 0 */
	struct rs_env_hit hit;
	double rgb[3];
	rs_trace_environment(&env, origin, dir, &hit, rgb);
	assert_true(hit.line);
	assert_true(fabs(rgb[0] - 0.25) < 1e-7);
	assert_int_equal(hit.cell_s, 8);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(each_axis_direction_picks_its_face),
	    cmocka_unit_test(exit_point_lies_on_the_face),
	    cmocka_unit_test(grid_lines_darken_by_line_scale),
	    cmocka_unit_test(face_edges_are_lines_and_cells_stay_in_range),
	    cmocka_unit_test(parallel_rays_from_different_origins_hit_different_cells),
	    cmocka_unit_test(zero_direction_gets_a_defined_colour),
	    cmocka_unit_test(origin_outside_the_cube_stays_finite),
	    cmocka_unit_test(zero_grid_fields_take_the_defaults),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
