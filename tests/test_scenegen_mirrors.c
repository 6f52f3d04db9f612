/* The mirrors scene (the paper's Table 3 size): name, triangle count, materials, windings. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_scene.h"
#include "raystream/rs_scenegen.h"

static struct rs_scene *build_mirrors(void)
{
	struct rs_scenegen_desc d;
	struct rs_scene *s = NULL;
	assert_int_equal(rs_scenegen_parse("mirrors", &d, NULL), RS_OK);
	assert_int_equal(d.kind, RS_SCENEGEN_MIRRORS);
	assert_int_equal(rs_scenegen_build(&d, &s, NULL), RS_OK);
	return s;
}

static void name_round_trips(void **state)
{
	(void)state;
	struct rs_scenegen_desc d = {.kind = RS_SCENEGEN_MIRRORS};
	char out[16];
	assert_int_equal(rs_scenegen_name(&d, out, sizeof out, NULL), RS_OK);
	assert_string_equal(out, "mirrors");
	assert_int_equal(rs_scenegen_parse("mirror", &d, NULL), RS_ERR_INVALID);
}

/* 25,254 triangles: floor 12 + 9 pillars x 12 diffuse; 3 spheres x 6,272 mirror; torus
 * 6,318 gold mirror. Nothing is glass. */
static void triangle_count_and_materials(void **state)
{
	(void)state;
	struct rs_scene *s = build_mirrors();
	size_t n = rs_scene_triangle_count(s), mirror = 0, gold = 0, diffuse = 0;
	const uint32_t *tm = rs_scene_triangle_materials(s);
	const struct rs_material *m = rs_scene_materials(s);
	assert_int_equal(n, RS_SCENEGEN_MIRRORS_TRIANGLES);
	assert_int_equal(n, 25254);
	for (size_t t = 0; t < n; t++) {
		const struct rs_material *mt = &m[tm[t]];
		assert_true(mt->transmittance == 0.0f);
		if (mt->reflectance >= 0.9f)
			mirror++;
		else if (mt->reflectance > 0.0f)
			gold++;
		else
			diffuse++;
	}
	assert_int_equal(mirror, 3 * 6272);
	assert_int_equal(gold, 6318);
	assert_int_equal(diffuse, 12 + 9 * 12);
	assert_int_equal(rs_scene_light_count(s), 4);
	rs_scene_destroy(&s);
}

/* Every curved mirror triangle is wound so its face normal agrees with its vertex normals
 * (outward), and none is degenerate: reflections depend on both. */
static void mirror_windings_agree_with_normals(void **state)
{
	(void)state;
	struct rs_scene *s = build_mirrors();
	const float *p = rs_scene_positions(s), *nr = rs_scene_normals(s);
	const uint32_t *idx = rs_scene_indices(s), *tm = rs_scene_triangle_materials(s);
	const struct rs_material *m = rs_scene_materials(s);
	for (size_t t = 0; t < rs_scene_triangle_count(s); t++) {
		if (m[tm[t]].reflectance == 0.0f)
			continue;
		const float *a = p + 3 * idx[3 * t], *b = p + 3 * idx[3 * t + 1],
		            *c = p + 3 * idx[3 * t + 2];
		double e1[3], e2[3], f[3];
		for (int k = 0; k < 3; k++) {
			e1[k] = b[k] - a[k];
			e2[k] = c[k] - a[k];
		}
		f[0] = e1[1] * e2[2] - e1[2] * e2[1];
		f[1] = e1[2] * e2[0] - e1[0] * e2[2];
		f[2] = e1[0] * e2[1] - e1[1] * e2[0];
		double len = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
		assert_true(len > 1e-8);
		for (int v = 0; v < 3; v++) {
			const float *n = nr + 3 * idx[3 * t + v];
			assert_true((f[0] * n[0] + f[1] * n[1] + f[2] * n[2]) / len > 0.5);
		}
	}
	rs_scene_destroy(&s);
}

/* The camera looks at the mirrors from above the floor, inside the environment cube. */
static void camera_sees_the_mirrors_from_above(void **state)
{
	(void)state;
	struct rs_scene *s = build_mirrors();
	const struct rs_camera *cam = rs_scene_camera(s);
	struct rs_environment env;
	rs_scene_environment(s, &env);
	assert_true(cam->eye[1] > 3.5);
	assert_true(fabs(cam->target[0]) < 1.0 && cam->target[1] > 0.0 && cam->target[1] < 3.5);
	for (int k = 0; k < 3; k++)
		assert_true(fabs(cam->eye[k] - env.center[k]) < env.half_size);
	rs_scene_destroy(&s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(name_round_trips),
	    cmocka_unit_test(triangle_count_and_materials),
	    cmocka_unit_test(mirror_windings_agree_with_normals),
	    cmocka_unit_test(camera_sees_the_mirrors_from_above),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
