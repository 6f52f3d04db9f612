/* rs_trace: mirror reflection, refraction through a slab, total internal reflection and
 * the Fresnel weights, checked against geometry worked out by hand. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "test_trace_render_fixture.h"

static const struct rs_material mirror = {.reflectance = 1.0f};

/* Environment cube of half-size 100 at the origin, face f coloured (0.1 + 0.1 f, 0.3, 0.9). */
static struct rs_environment test_env(void)
{
	struct rs_environment env = {.half_size = 100};
	for (int f = 0; f < 6; ++f) {
		env.face_color[f][0] = 0.1f + 0.1f * (float)f;
		env.face_color[f][1] = 0.3f;
		env.face_color[f][2] = 0.9f;
	}
	return env;
}

static void mirror_shows_the_environment_at_the_reflected_exit_point(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	fx_quad(fx.scene, 2, 0.0, -10, 10, 0, fx_material(fx.scene, mirror));
	struct rs_environment env = test_env();
	assert_int_equal(rs_scene_set_environment(fx.scene, &env, NULL), RS_OK);
	fx_pack(&fx, RS_BVH_SAH);
	const double eye[3] = {0, 0, 5}, p[3] = {1.5, 0.5, 0};
	struct rs_trace_segment seg[2];
	struct rs_trace_path path = fx_path(&fx, eye, p, 2, seg);
	assert_int_equal(path.segments, 2);
	assert_int_equal(path.state, RS_RAY_ENVIRONMENT);
	/* reflected direction (1.5, 0.5, 5) / |.|: leaves through +z (face 4) at
	 * (31.5, 10.5, 100), inside a grid cell (not on a line), so the colour is face 4's
	 * exactly; the mirror itself adds nothing (no diffuse, no specular) */
	double len = sqrt(1.5 * 1.5 + 0.5 * 0.5 + 25.0);
	assert_true(fabs(seg[1].ray.dir[0] - 1.5 / len) < 1e-12);
	assert_true(fabs(seg[1].ray.dir[2] - 5.0 / len) < 1e-12);
	assert_true(seg[1].throughput == 1.0);
	for (int c = 0; c < 3; ++c)
		assert_true(fabs(path.rgb[c] - env.face_color[4][c]) < 1e-12);
	fx_free(&fx);
}

static void mirror_shows_an_object_at_its_reflected_position(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	fx_quad(fx.scene, 2, 0.0, -10, 10, 0, fx_material(fx.scene, mirror));
	/* a small card at z = 3 facing down, triangles 2 and 3 */
	struct rs_material card = {.diffuse = {1, 1, 1}};
	fx_rect(fx.scene, 2, 3.0, 1.8, 3.0, 0.2, 1.4, 1, fx_material(fx.scene, card));
	fx_pack(&fx, RS_BVH_SAH);
	const double eye[3] = {0, 0, 5}, p[3] = {1.5, 0.5, 0};
	struct rs_trace_segment seg[3];
	struct rs_trace_path path = fx_path(&fx, eye, p, 3, seg);
	assert_int_equal(path.state, RS_RAY_DIFFUSE);
	assert_int_equal(path.segments, 2);
	assert_true(seg[1].hit.triangle == 2 || seg[1].hit.triangle == 3);
	/* the reflected ray reaches z = 3 at (1.5 + 0.9, 0.5 + 0.3); the origin offset
	 * (1e-6 x scene extent 20) bounds the error */
	double hp[3];
	for (int a = 0; a < 3; ++a)
		hp[a] = seg[1].ray.origin[a] + seg[1].hit.t * seg[1].ray.dir[a];
	assert_true(fabs(hp[0] - 2.4) < 1e-4 && fabs(hp[1] - 0.8) < 1e-4);
	assert_true(fabs(hp[2] - 3.0) < 1e-6);
	/* the card is lit by ambient only (no lights): 0.1 x white, through a weight-1 mirror */
	assert_true(fabs(path.rgb[0] - 0.1) < 1e-12);
	fx_free(&fx);
}

/* A glass slab z in [-1, 0], 100 x 100 wide. */
static void slab_scene(struct fx *fx, struct rs_material glass)
{
	fx->scene = fx_scene();
	const double lo[3] = {-50, -50, -1}, hi[3] = {50, 50, 0};
	fx_box(fx->scene, lo, hi, fx_material(fx->scene, glass));
	struct rs_environment env = test_env();
	env.half_size = 200;
	assert_int_equal(rs_scene_set_environment(fx->scene, &env, NULL), RS_OK);
	fx_pack(fx, RS_BVH_SAH);
}

static void slab_displaces_a_ray_by_the_snell_offset(void **state)
{
	struct fx fx;
	slab_scene(&fx, (struct rs_material){.transmittance = 1.0f, .ior = 1.5f});
	double th = 30.0 * RS_PI / 180.0, tt = asin(sin(th) / 1.5);
	const double eye[3] = {0, 0, 5}, towards[3] = {sin(th), 0, 5 - cos(th)};
	struct rs_trace_segment seg[3];
	struct rs_trace_path path = fx_path(&fx, eye, towards, 3, seg);
	assert_int_equal(path.segments, 3);
	assert_int_equal(path.state, RS_RAY_ENVIRONMENT);
	/* inside: bent towards the normal by Snell */
	assert_true(fabs(seg[1].ray.dir[0] - sin(tt)) < 1e-12);
	assert_true(fabs(seg[1].ray.dir[2] + cos(tt)) < 1e-12);
	/* out again: parallel to the incoming ray... */
	assert_true(fabs(seg[2].ray.dir[0] - sin(th)) < 1e-12);
	assert_true(fabs(seg[2].ray.dir[2] + cos(th)) < 1e-12);
	/* ...and shifted sideways by thickness * sin(th - tt) / cos(tt) = 0.1938. The
	 * offsets (1e-6 x extent 100 = 1e-4 along the normal) bound the error. */
	double dx = seg[2].ray.origin[0] - eye[0], dz = seg[2].ray.origin[2] - eye[2];
	double shift = fabs(dx * -cos(th) - dz * sin(th)); /* |(o2 - o0) x dir| in the xz plane */
	assert_true(fabs(shift - sin(th - tt) / cos(tt)) < 1e-3);
	assert_true(fabs(seg[2].ray.origin[0] - (5 * tan(th) + tan(tt))) < 1e-3);
	assert_true(seg[1].throughput == 1.0 && seg[2].throughput == 1.0);
	fx_free(&fx);
}

static void total_internal_reflection_reflects_with_the_transmittance(void **state)
{
	struct fx fx;
	slab_scene(&fx, (struct rs_material){.transmittance = 0.9f, .ior = 1.5f});
	/* from inside the glass up at 60 degrees, beyond the critical 41.8 */
	double th = 60.0 * RS_PI / 180.0;
	const double inside[3] = {0, 0, -0.5}, towards[3] = {sin(th), 0, -0.5 + cos(th)};
	struct rs_trace_segment seg[2];
	fx_path(&fx, inside, towards, 2, seg);
	assert_int_equal(seg[0].state, RS_RAY_ACTIVE);
	assert_true(fabs(seg[1].ray.dir[0] - sin(th)) < 1e-12);
	assert_true(fabs(seg[1].ray.dir[2] + cos(th)) < 1e-12); /* mirrored, back down */
	assert_true(seg[1].ray.origin[2] < 0.0);                /* stays inside */
	assert_true(fabs(seg[1].throughput - 0.9) < 1e-7);      /* float 0.9f */
	fx_free(&fx);
}

static void fixed_transmittance_weights_the_refracted_ray(void **state)
{
	struct fx fx;
	slab_scene(&fx,
	           (struct rs_material){.reflectance = 0.3f, .transmittance = 0.6f, .ior = 1.5f});
	const double eye[3] = {0.3, 0.2, 5}, below[3] = {0.3, 0.2, 0};
	struct rs_trace_segment seg[2];
	fx_path(&fx, eye, below, 2, seg);
	/* transmittance 0.6 > reflectance 0.3: the single path refracts, weight 0.6 */
	assert_true(seg[1].ray.dir[2] < 0.0);
	assert_true(fabs(seg[1].throughput - 0.6) < 1e-7);
	fx_free(&fx);
}

static void fresnel_at_normal_incidence_transmits_one_minus_r0(void **state)
{
	struct fx fx;
	slab_scene(&fx, (struct rs_material){.reflectance = 1.0f,
	                                     .transmittance = 1.0f,
	                                     .ior = 1.5f,
	                                     .flags = RS_MATERIAL_FRESNEL});
	const double eye[3] = {0.3, 0.2, 5}, below[3] = {0.3, 0.2, 0};
	struct rs_trace_segment seg[2];
	fx_path(&fx, eye, below, 2, seg);
	/* R0 = ((1.5 - 1) / (1.5 + 1))^2 = 0.04: refraction wins with weight 0.96 */
	assert_true(seg[1].ray.dir[2] < 0.0);
	assert_true(fabs(seg[1].throughput - 0.96) < 1e-7);
	fx_free(&fx);
}

static void fresnel_mirror_at_normal_incidence_reflects_r0(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_material m = {.reflectance = 1.0f, .ior = 1.5f, .flags = RS_MATERIAL_FRESNEL};
	fx_quad(fx.scene, 2, 0.0, -10, 10, 0, fx_material(fx.scene, m));
	fx_pack(&fx, RS_BVH_SAH);
	const double eye[3] = {0.3, 0.2, 5}, below[3] = {0.3, 0.2, 0};
	struct rs_trace_segment seg[2];
	fx_path(&fx, eye, below, 2, seg);
	assert_true(seg[1].ray.dir[2] > 0.0);
	assert_true(fabs(seg[1].throughput - 0.04) < 1e-7);
	fx_free(&fx);
}

static void fresnel_glass_turns_into_a_mirror_at_grazing_incidence(void **state)
{
	struct fx fx;
	slab_scene(&fx, (struct rs_material){.reflectance = 1.0f,
	                                     .transmittance = 1.0f,
	                                     .ior = 1.5f,
	                                     .flags = RS_MATERIAL_FRESNEL});
	double th = 85.0 * RS_PI / 180.0;
	const double eye[3] = {-20, 0, 5}, towards[3] = {-20 + sin(th), 0, 5 - cos(th)};
	struct rs_trace_segment seg[2];
	fx_path(&fx, eye, towards, 2, seg);
	/* Schlick at 85 degrees: 0.04 + 0.96 (1 - cos 85)^5 = 0.648 > 1 - 0.648 */
	double f = rs_trace_fresnel_schlick(cos(th), 1.0, 1.5);
	assert_true(f > 0.6 && f < 0.7);
	assert_true(seg[1].ray.dir[2] > 0.0);
	assert_true(fabs(seg[1].throughput - f) < 1e-9);
	fx_free(&fx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(mirror_shows_the_environment_at_the_reflected_exit_point),
	    cmocka_unit_test(mirror_shows_an_object_at_its_reflected_position),
	    cmocka_unit_test(slab_displaces_a_ray_by_the_snell_offset),
	    cmocka_unit_test(total_internal_reflection_reflects_with_the_transmittance),
	    cmocka_unit_test(fixed_transmittance_weights_the_refracted_ray),
	    cmocka_unit_test(fresnel_at_normal_incidence_transmits_one_minus_r0),
	    cmocka_unit_test(fresnel_mirror_at_normal_incidence_reflects_r0),
	    cmocka_unit_test(fresnel_glass_turns_into_a_mirror_at_grazing_incidence),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
