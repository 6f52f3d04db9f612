/* rs_trace: Phong normals interpolated by the hit's barycentric u, v, double-sided
 * surfaces, and which lights take part. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "test_trace_render_fixture.h"

static const struct rs_material white = {.diffuse = {1, 1, 1}};

/* One triangle in z = 0 with winding normal +z: v0 = 0, v1 = 4 x, v2 = 4 y. */
static void add_triangle(struct rs_scene *scene, const float *normals, uint32_t material)
{
	const float pos[9] = {0, 0, 0, 4, 0, 0, 0, 4, 0};
	const uint32_t idx[3] = {0, 1, 2};
	fx_mesh(scene, pos, 3, idx, 1, normals, material);
}

static struct rs_trace_path path_with(const struct fx *fx, const double from[3], const double to[3],
                                      uint32_t lights, struct rs_trace_segment *seg)
{
	struct rs_ray ray = {.origin = {from[0], from[1], from[2]},
	                     .dir = {to[0] - from[0], to[1] - from[1], to[2] - from[2]},
	                     .tmax = INFINITY,
	                     .skip_slot = RS_NO_SLOT};
	struct rs_trace_desc d = {.passes = 1, .lights = lights};
	struct rs_trace_path p;
	assert_int_equal(rs_trace_ray_path(fx->scene, &fx->packed, &d, &ray, &p, seg, NULL), RS_OK);
	return p;
}

static void normals_are_interpolated_by_the_hit_barycentrics(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	const float s = (float)(1.0 / sqrt(2.0));
	const float normals[9] = {0, 0, 1, s, 0, s, 0, s, s};
	add_triangle(fx.scene, normals, fx_material(fx.scene, white));
	const double lp[3] = {1, 1, 1000};
	fx_light(fx.scene, lp[0], lp[1], lp[2], 1, 1, 1);
	fx_pack(&fx, RS_BVH_SAH);
	const double pts[3][2] = {{1, 1}, {0.5, 3}, {2.5, 0.4}};
	for (int k = 0; k < 3; ++k) {
		const double from[3] = {pts[k][0], pts[k][1], 5}, to[3] = {pts[k][0], pts[k][1], 0};
		struct rs_trace_segment seg[1];
		struct rs_trace_path p = path_with(&fx, from, to, 0, seg);
		double u = pts[k][0] / 4, v = pts[k][1] / 4, w = 1 - u - v;
		/* barycentrics of an axis-aligned triangle: exact up to rounding */
		assert_true(fabs(seg[0].hit.u - u) < 1e-12 && fabs(seg[0].hit.v - v) < 1e-12);
		double n[3] = {u * normals[3] + v * normals[6], u * normals[4] + v * normals[7],
		               w * normals[2] + u * normals[5] + v * normals[8]};
		double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
		double l[3] = {lp[0] - pts[k][0], lp[1] - pts[k][1], lp[2]};
		double ll = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
		double ndotl = (n[0] * l[0] + n[1] * l[1] + n[2] * l[2]) / (len * ll);
		/* the scene stores normals as floats: 1e-6 covers their rounding */
		assert_true(fabs(p.rgb[0] - (0.1 + ndotl)) < 1e-6);
		/* and it differs from flat shading, so the interpolation is visible */
		assert_true(fabs(p.rgb[0] - (0.1 + lp[2] / ll)) > 0.02);
	}
	fx_free(&fx);
}

static void a_surface_is_lit_from_either_side(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	add_triangle(fx.scene, NULL, fx_material(fx.scene, white));
	fx_light(fx.scene, 1, 1, -10, 1, 1, 1); /* below, on the back side of the winding */
	fx_pack(&fx, RS_BVH_SAH);
	const double below[3] = {1, 1, -5}, above[3] = {1, 1, 5}, pt[3] = {1, 1, 0};
	struct rs_trace_path p = path_with(&fx, below, pt, 0, NULL);
	assert_int_equal(p.shadow_rays, 1);
	assert_true(fabs(p.rgb[0] - 1.1) < 1e-12); /* ambient 0.1 + N.L = 1 */
	/* seen from above, the light is on the far side: ambient only, no feeler */
	p = path_with(&fx, above, pt, 0, NULL);
	assert_int_equal(p.shadow_rays, 0);
	assert_true(fabs(p.rgb[0] - 0.1) < 1e-12);
	fx_free(&fx);
}

static void only_the_first_n_lights_are_used(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	add_triangle(fx.scene, NULL, fx_material(fx.scene, white));
	fx_light(fx.scene, 1, 1, 10, 0.5, 0.5, 0.5);
	fx_light(fx.scene, 1, 1, 20, 0.25, 0.25, 0.25);
	fx_pack(&fx, RS_BVH_SAH);
	const double above[3] = {1, 1, 5}, pt[3] = {1, 1, 0};
	struct rs_trace_path one = path_with(&fx, above, pt, 1, NULL);
	struct rs_trace_path all = path_with(&fx, above, pt, 0, NULL);
	assert_int_equal(one.shadow_rays, 1);
	assert_int_equal(all.shadow_rays, 2);
	assert_true(fabs(one.rgb[0] - 0.6) < 1e-12);  /* no fall-off: 0.1 + 0.5 */
	assert_true(fabs(all.rgb[0] - 0.85) < 1e-12); /* + 0.25 */
	fx_free(&fx);
}

static void coloured_light_scales_each_channel(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_material m = {.diffuse = {0.5f, 0.25f, 1.0f}};
	add_triangle(fx.scene, NULL, fx_material(fx.scene, m));
	fx_light(fx.scene, 1, 1, 10, 1.0, 2.0, 0.0);
	fx_pack(&fx, RS_BVH_SAH);
	const double above[3] = {1, 1, 5}, pt[3] = {1, 1, 0};
	struct rs_trace_path p = path_with(&fx, above, pt, 0, NULL);
	assert_true(fabs(p.rgb[0] - (0.05 + 0.5)) < 1e-12);
	assert_true(fabs(p.rgb[1] - (0.025 + 0.5)) < 1e-12);
	assert_true(fabs(p.rgb[2] - 0.1) < 1e-12); /* ambient is not coloured by lights */
	fx_free(&fx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(normals_are_interpolated_by_the_hit_barycentrics),
	    cmocka_unit_test(a_surface_is_lit_from_either_side),
	    cmocka_unit_test(only_the_first_n_lights_are_used),
	    cmocka_unit_test(coloured_light_scales_each_channel),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
