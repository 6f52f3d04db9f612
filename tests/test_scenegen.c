/* rs_scenegen: scene names, the paper's triangle counts, CowN herd placement, stage,
 * materials, camera, lights and environment exactly as shared/SCENES.md specifies. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "contract.h"
#include "raystream/rs_load.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_scenegen.h"
#include "test_load_fixture.h"

#define COW_PATH RS_DATA_DIR "/cow.obj"
#define COW_TRIS 5804u
#define PI 3.14159265358979323846

static struct rs_scene *build(enum rs_scenegen_kind kind, uint32_t cows)
{
	struct rs_scenegen_desc d = {.kind = kind, .cows = cows, .cow_path = COW_PATH};
	struct rs_scene *s = NULL;
	struct rs_error err;

	assert_int_equal(rs_scenegen_build(&d, &s, &err), RS_OK);
	assert_non_null(s);
	return s;
}

/* Bounds of triangles [first, first + count). */
static void tri_bounds(const struct rs_scene *s, size_t first, size_t count, struct rs_bounds *b)
{
	const double *p = rs_scene_positions_f64(s); /* the generator works in double */
	const uint32_t *idx = rs_scene_indices(s);

	for (int k = 0; k < 3; k++) {
		b->lo[k] = INFINITY;
		b->hi[k] = -INFINITY;
	}
	for (size_t t = first; t < first + count; t++)
		for (int c = 0; c < 3; c++)
			for (int k = 0; k < 3; k++) {
				double v = p[3 * idx[3 * t + c] + k];

				b->lo[k] = fmin(b->lo[k], v);
				b->hi[k] = fmax(b->hi[k], v);
			}
}

static void parse_accepts_scene_names(void **state)
{
	struct rs_scenegen_desc d;

	assert_int_equal(rs_scenegen_parse("box", &d, NULL), RS_OK);
	assert_int_equal(d.kind, RS_SCENEGEN_BOX);
	assert_int_equal(rs_scenegen_parse("cow1", &d, NULL), RS_OK);
	assert_true(d.kind == RS_SCENEGEN_COW && d.cows == 1 && d.cow_path == NULL);
	assert_int_equal(rs_scenegen_parse("cow17", &d, NULL), RS_OK);
	assert_int_equal(d.cows, 17);
	assert_int_equal(rs_scenegen_parse("cow1024", &d, NULL), RS_OK);
	assert_int_equal(d.cows, 1024);
}

static void parse_rejects_bad_names(void **state)
{
	static const char *bad[] = {"",      "cow",  "cow0", "cow01",   "cow-1",
	                            "cow1x", "Cow1", "box2", "cow1025", "cow99999999999999999999",
	                            "tree"};
	struct rs_scenegen_desc d;
	struct rs_error err;

	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		assert_int_equal(rs_scenegen_parse(bad[i], &d, &err), RS_ERR_INVALID);
		assert_null(strchr(err.message, '\n'));
	}
	RS_EXPECT_CONTRACT_VIOLATION(rs_scenegen_parse(NULL, &d, &err));
}

static void name_is_canonical(void **state)
{
	struct rs_scenegen_desc d = {.kind = RS_SCENEGEN_COW, .cows = 0};
	char out[16];

	assert_int_equal(rs_scenegen_name(&d, out, sizeof(out), NULL), RS_OK);
	assert_string_equal(out, "cow1");
	d.cows = 17;
	assert_int_equal(rs_scenegen_name(&d, out, sizeof(out), NULL), RS_OK);
	assert_string_equal(out, "cow17");
	d.kind = RS_SCENEGEN_BOX;
	assert_int_equal(rs_scenegen_name(&d, out, sizeof(out), NULL), RS_OK);
	assert_string_equal(out, "box");
	assert_int_equal(rs_scenegen_name(&d, out, 3, NULL), RS_ERR_LIMIT);
}

/* The paper's Table 1 triangle counts. */
static void triangle_counts_match_the_paper(void **state)
{
	static const struct {
		enum rs_scenegen_kind kind;
		uint32_t cows;
		size_t tris;
	} want[] = {{RS_SCENEGEN_BOX, 0, 153},   {RS_SCENEGEN_COW, 1, 5837},
	            {RS_SCENEGEN_COW, 2, 11641}, {RS_SCENEGEN_COW, 5, 29053},
	            {RS_SCENEGEN_COW, 9, 52269}, {RS_SCENEGEN_COW, 17, 98701}};

	for (size_t i = 0; i < sizeof(want) / sizeof(want[0]); i++) {
		struct rs_scene *s = build(want[i].kind, want[i].cows);

		assert_int_equal(rs_scene_triangle_count(s), want[i].tris);
		assert_int_equal(rs_scene_light_count(s), 4);
		rs_scene_destroy(&s);
	}
}

/*
 * Cow5: cols = 3, rows = 2, lattice centred on the origin, spacing 12 x 8, rows towards +z.
 * Copy i, turned back by -i*37 degrees about its grid point, must be the original cow
 * with its bounding-box centre on (grid x, centre y + 3.637, grid z). Tolerance 1e-5:
 * coordinates up to ~20 are rounded to float (half an ulp ~1e-6) before we turn them back.
 */
static void herd_copies_sit_on_their_grid_points(void **state)
{
	static const double grid[5][2] = {{-12, -4}, {0, -4}, {12, -4}, {-12, 4}, {0, 4}};
	struct rs_scene *s = build(RS_SCENEGEN_COW, 5), *cow = NULL;
	struct rs_bounds cb;
	const float *p = rs_scene_positions(s), *q;
	size_t nv;

	assert_int_equal(rs_scene_create(NULL, &cow, NULL), RS_OK);
	assert_int_equal(rs_load_mesh_file(NULL, COW_PATH, cow, NULL), RS_OK);
	rs_scene_bounds(cow, &cb);
	q = rs_scene_positions(cow);
	nv = rs_scene_vertex_count(cow);
	for (int i = 0; i < 5; i++) {
		double a = -i * 37.0 * PI / 180.0, cs = cos(a), sn = sin(a);

		for (size_t v = 0; v < nv; v++) {
			const float *w = &p[3 * (i * nv + v)];
			double x = w[0] - grid[i][0], z = w[2] - grid[i][1];
			/* turned back: same rotation formula with the negative angle */
			double ux = x * cs + z * sn, uz = -x * sn + z * cs;

			assert_near(ux, q[3 * v] - 0.5 * (cb.lo[0] + cb.hi[0]), 1e-5);
			assert_near(w[1], q[3 * v + 1] + 3.637, 1e-5);
			assert_near(uz, q[3 * v + 2] - 0.5 * (cb.lo[2] + cb.hi[2]), 1e-5);
		}
	}
	rs_scene_destroy(&cow);
	rs_scene_destroy(&s);
}

/* Right-handed turn: the cow's +x end (its extreme vertex) moves towards -z. */
static void herd_turn_moves_plus_x_towards_minus_z(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_COW, 2);
	const float *p = rs_scene_positions(s);
	size_t nv = rs_scene_vertex_count(s), per = 0, far = 0;

	/* Copies have equal vertex counts; the stage comes after them. */
	for (size_t t = 0; t < 2 * COW_TRIS; t++)
		per = (size_t)fmax((double)per, (double)rs_scene_indices(s)[3 * t] + 1);
	per /= 2;
	assert_true(per > 0 && per < nv);
	for (size_t v = 0; v < per; v++)
		if (p[3 * v] > p[3 * far])
			far = v;
	/* Cow2: cols 2, rows 1: copy 0 at x = -6, copy 1 (turned 37 deg) at x = +6, z = 0. */
	assert_true(p[3 * (per + far) + 2] < p[3 * far + 2] - 1.0);
	assert_true(p[3 * (per + far)] - 6.0 > 0.0);
	rs_scene_destroy(&s);
}

/* Feet on the floor: the cow's lowest point is -3.637036, lifted by 3.637. */
static void herd_stands_on_the_floor(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_COW, 1);
	struct rs_bounds h;

	tri_bounds(s, 0, COW_TRIS, &h);
	assert_near(h.lo[1], -0.000036, 1e-5);
	rs_scene_destroy(&s);
}

/* Stage after the herd: floor 12, mirror 12, prism 8, sail 1 (exact floats compared to
 * the double spec values within float rounding, 1e-5 at these magnitudes). */
static void stage_parts_follow_the_spec(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_COW, 5);
	size_t t0 = 5 * COW_TRIS;
	struct rs_bounds h, fl, mi, pr, sa;
	const struct rs_material *m = rs_scene_materials(s);
	const uint32_t *tm = rs_scene_triangle_materials(s);
	double hcx, hcz;

	assert_int_equal(rs_scene_triangle_count(s), t0 + RS_SCENEGEN_STAGE_TRIANGLES);
	tri_bounds(s, 0, t0, &h);
	hcx = 0.5 * (h.lo[0] + h.hi[0]);
	hcz = 0.5 * (h.lo[2] + h.hi[2]);
	tri_bounds(s, t0, 12, &fl);
	tri_bounds(s, t0 + 12, 12, &mi);
	tri_bounds(s, t0 + 24, 8, &pr);
	tri_bounds(s, t0 + 32, 1, &sa);
	/* floor: top y = 0, 0.5 thick, herd + 4 on every side */
	assert_near(fl.hi[1], 0.0, 1e-6);
	assert_near(fl.lo[1], -0.5, 1e-6);
	assert_near(fl.lo[0], h.lo[0] - 4.0, 1e-5);
	assert_near(fl.hi[0], h.hi[0] + 4.0, 1e-5);
	assert_near(fl.lo[2], h.lo[2] - 4.0, 1e-5);
	assert_near(fl.hi[2], h.hi[2] + 4.0, 1e-5);
	/* mirror: floor-wide, y 0..8, 0.3 thick at the back edge */
	assert_near(mi.lo[0], fl.lo[0], 1e-6);
	assert_near(mi.hi[0], fl.hi[0], 1e-6);
	assert_near(mi.lo[1], 0.0, 1e-6);
	assert_near(mi.hi[1], 8.0, 1e-6);
	assert_near(mi.lo[2], fl.lo[2], 1e-6);
	assert_near(mi.hi[2] - mi.lo[2], 0.3, 1e-5);
	/* prism: 3 high, 1 mm above the floor (no coplanar glass face), circumradius 1.2,
	 * vertex towards +z at max z + 2 */
	assert_near(pr.lo[1], 1e-3, 1e-6);
	assert_near(pr.hi[1], 3.0 + 1e-3, 1e-6);
	assert_near(pr.hi[2], h.hi[2] + 2.0 + 1.2, 1e-5);
	assert_near(pr.lo[2], h.hi[2] + 2.0 - 0.6, 1e-5);
	assert_near(0.5 * (pr.lo[0] + pr.hi[0]), hcx, 1e-5);
	assert_near(pr.hi[0] - pr.lo[0], 2.0 * 1.2 * sin(PI / 3.0), 1e-5);
	/* sail: lowest edge 1 above the herd, over its left quarter, at its centre z */
	assert_near(sa.lo[1], h.hi[1] + 1.0, 1e-5);
	assert_near(0.5 * (sa.lo[0] + sa.hi[0]), h.lo[0] + 0.125 * (h.hi[0] - h.lo[0]), 1e-5);
	assert_near(sa.hi[2], hcz, 1e-5);
	assert_near(sa.hi[0] - sa.lo[0], 5.0, 1e-5);
	/* materials */
	assert_true(m[tm[0]].diffuse[0] == 0.55f && m[tm[0]].specular == 0.3f &&
	            m[tm[0]].shininess == 32.0f && m[tm[0]].reflectance == 0.25f);
	assert_true(m[tm[t0]].diffuse[0] == 0.8f && m[tm[t0]].reflectance == 0.0f);
	assert_true(m[tm[t0 + 12]].diffuse[0] == 0.1f && m[tm[t0 + 12]].reflectance == 0.9f);
	assert_true(m[tm[t0 + 24]].ior == 1.5f && m[tm[t0 + 24]].transmittance == 0.9f);
	assert_true(m[tm[t0 + 32]].diffuse[2] == 0.8f && m[tm[t0 + 32]].diffuse[1] == 0.4f);
	assert_true(rs_scene_ambient(s) == 0.1);
	rs_scene_destroy(&s);
}

/* Floor, mirror and prism are closed convex solids: the face normals stored per vertex
 * point away from the part's centre, and the winding agrees with them (the tracers take
 * "entering glass" from the winding). */
static void stage_normals_point_outwards(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_COW, 1);
	const float *p = rs_scene_positions(s), *n = rs_scene_normals(s);
	const uint32_t *idx = rs_scene_indices(s);
	static const size_t part[3][2] = {{0, 12}, {12, 12}, {24, 8}};

	for (int k = 0; k < 3; k++) {
		struct rs_bounds b;
		size_t first = COW_TRIS + part[k][0];

		tri_bounds(s, first, part[k][1], &b);
		for (size_t t = first; t < first + part[k][1]; t++) {
			uint32_t v = idx[3 * t];
			const float *a = &p[3 * v], *b1 = &p[3 * idx[3 * t + 1]],
			            *c1 = &p[3 * idx[3 * t + 2]];
			double e1[3], e2[3], d = 0.0, w;

			for (int c = 0; c < 3; c++) {
				double mid = 0.0;

				for (int j = 0; j < 3; j++)
					mid += p[3 * idx[3 * t + j] + c] / 3.0;
				d += n[3 * v + c] * (mid - 0.5 * (b.lo[c] + b.hi[c]));
				e1[c] = b1[c] - a[c];
				e2[c] = c1[c] - a[c];
			}
			w = n[3 * v] * (e1[1] * e2[2] - e1[2] * e2[1]) +
			    n[3 * v + 1] * (e1[2] * e2[0] - e1[0] * e2[2]) +
			    n[3 * v + 2] * (e1[0] * e2[1] - e1[1] * e2[0]);
			assert_true(d > 0.0);
			assert_true(w > 0.0);
		}
	}
	rs_scene_destroy(&s);
}

/* Camera rule: target the herd centre from 30 deg above on +z, at r / sin(22.5 deg). */
static void camera_follows_the_rule(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_COW, 9);
	const struct rs_camera *c = rs_scene_camera(s);
	struct rs_bounds h;
	double r = 0.0, d = 0.0, dy;

	tri_bounds(s, 0, 9 * COW_TRIS, &h);
	for (int k = 0; k < 3; k++) {
		r += (h.hi[k] - h.lo[k]) * (h.hi[k] - h.lo[k]);
		d += (c->eye[k] - c->target[k]) * (c->eye[k] - c->target[k]);
		assert_near(c->target[k], 0.5 * (h.lo[k] + h.hi[k]), 1e-9);
	}
	r = 0.5 * sqrt(r);
	d = sqrt(d);
	dy = c->eye[1] - c->target[1];
	/* 1e-9 relative: pure double arithmetic on the same bounds */
	assert_near(d, r / sin(22.5 * PI / 180.0), 1e-9 * d);
	assert_near(asin(dy / d) * 180.0 / PI, 30.0, 1e-9);
	assert_true(c->eye[2] > c->target[2]);
	assert_near(c->eye[0], c->target[0], 1e-9);
	assert_true(c->up[1] > 0.0 && c->up[0] == 0.0 && c->up[2] == 0.0);
	assert_true(c->fov_y_deg == 45.0 && c->width == 512 && c->height == 512);
	rs_scene_destroy(&s);
}

static void lights_sit_at_their_offsets(void **state)
{
	static const double off[4][3] = {{-10, 25, 20}, {15, 20, 10}, {0, 30, -15}, {-20, 12, -5}};
	struct rs_scene *s = build(RS_SCENEGEN_COW, 2);
	const struct rs_light *l = rs_scene_lights(s);
	struct rs_bounds h;

	tri_bounds(s, 0, 2 * COW_TRIS, &h);
	assert_int_equal(rs_scene_light_count(s), 4);
	for (int i = 0; i < 4; i++)
		for (int k = 0; k < 3; k++) {
			assert_near(l[i].position[k], 0.5 * (h.lo[k] + h.hi[k]) + off[i][k], 1e-9);
			assert_true(l[i].color[k] == 1.0);
		}
	rs_scene_destroy(&s);
}

static void environment_cube_follows_the_rule(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_COW, 5);
	struct rs_environment env;
	struct rs_bounds b;
	double extent = 0.0;

	rs_scene_bounds(s, &b);
	rs_scene_environment(s, &env);
	for (int k = 0; k < 3; k++) {
		assert_near(env.center[k], 0.5 * (b.lo[k] + b.hi[k]), 1e-9);
		extent = fmax(extent, b.hi[k] - b.lo[k]);
	}
	assert_near(env.half_size, 2.0 * extent, 1e-9);
	assert_int_equal(env.grid, 16);
	for (int f = 0; f < 6; f++)
		for (int g = f + 1; g < 6; g++)
			assert_memory_not_equal(env.face_color[f], env.face_color[g],
			                        sizeof(env.face_color[f]));
	rs_scene_destroy(&s);
}

/* Box: the camera rule on the contents puts the eye inside the closed room (walls are
 * 0.2 thick, so the interior is the scene bounds shrunk by 0.2); lights under the
 * ceiling, L1 at its centre. */
static void box_camera_and_lights_are_inside(void **state)
{
	struct rs_scene *s = build(RS_SCENEGEN_BOX, 0);
	const struct rs_camera *c = rs_scene_camera(s);
	const struct rs_light *l = rs_scene_lights(s);
	struct rs_bounds b;

	rs_scene_bounds(s, &b);
	for (int k = 0; k < 3; k++) {
		assert_true(c->eye[k] > b.lo[k] + 0.2 && c->eye[k] < b.hi[k] - 0.2);
		for (int i = 0; i < 4; i++)
			assert_true(l[i].position[k] > b.lo[k] + 0.2 &&
			            l[i].position[k] < b.hi[k] - 0.2);
	}
	/* the room's walls are float coordinates ~10: half an ulp is ~5e-7 */
	assert_near(l[0].position[0], 0.5 * (b.lo[0] + b.hi[0]), 1e-6);
	assert_near(l[0].position[2], 0.5 * (b.lo[2] + b.hi[2]), 1e-6);
	for (int i = 0; i < 4; i++)
		assert_true(l[i].position[1] > b.hi[1] - 0.2 - 0.5);
	assert_int_equal(rs_scene_material_count(s), 9);
	rs_scene_destroy(&s);
}

static void build_errors_are_reported(void **state)
{
	struct rs_scenegen_desc d = {.kind = RS_SCENEGEN_COW, .cows = 1};
	struct rs_scene *s = NULL;
	struct rs_error err;

	/* No path: the shipped cow, unless RS_DATA_DIR names a folder without it. */
	setenv("RS_DATA_DIR", "/nonexistent", 1);
	assert_int_equal(rs_scenegen_build(&d, &s, &err), RS_ERR_NOT_FOUND);
	assert_non_null(strstr(err.message, "RS_DATA_DIR (/nonexistent)"));
	assert_null(s);
	unsetenv("RS_DATA_DIR");
	assert_int_equal(rs_scenegen_build(&d, &s, &err), RS_OK);
	assert_int_equal(rs_scene_triangle_count(s), 5804 + RS_SCENEGEN_STAGE_TRIANGLES);
	rs_scene_destroy(&s);
	d.cow_path = "/nonexistent/cow.obj";
	assert_int_equal(rs_scenegen_build(&d, &s, &err), RS_ERR_NOT_FOUND);
	assert_non_null(strstr(err.message, "cow.obj"));
	assert_null(s);
	d.cow_path = COW_PATH;
	d.cows = RS_SCENEGEN_MAX_COWS + 1;
	assert_int_equal(rs_scenegen_build(&d, &s, &err), RS_ERR_INVALID);
	d.kind = (enum rs_scenegen_kind)7;
	assert_int_equal(rs_scenegen_build(&d, &s, &err), RS_ERR_INVALID);
	assert_null(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(parse_accepts_scene_names),
	    cmocka_unit_test(parse_rejects_bad_names),
	    cmocka_unit_test(name_is_canonical),
	    cmocka_unit_test(triangle_counts_match_the_paper),
	    cmocka_unit_test(herd_copies_sit_on_their_grid_points),
	    cmocka_unit_test(herd_turn_moves_plus_x_towards_minus_z),
	    cmocka_unit_test(herd_stands_on_the_floor),
	    cmocka_unit_test(stage_parts_follow_the_spec),
	    cmocka_unit_test(stage_normals_point_outwards),
	    cmocka_unit_test(camera_follows_the_rule),
	    cmocka_unit_test(lights_sit_at_their_offsets),
	    cmocka_unit_test(environment_cube_follows_the_rule),
	    cmocka_unit_test(box_camera_and_lights_are_inside),
	    cmocka_unit_test(build_errors_are_reported),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
