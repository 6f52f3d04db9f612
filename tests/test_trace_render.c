/* rs_trace: rs_trace_render() against analytic answers: Phong colour of a lit plane,
 * shadows, depth, ray states, passes, hit numbers, row ranges and bad descriptors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "contract.h"
#include "test_trace_render_fixture.h"

static const struct rs_material grey = {.diffuse = {0.5f, 0.5f, 0.5f}};
static const struct rs_material mirror = {.reflectance = 0.8f};

static void lit_plane_matches_the_phong_formula(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_material m = {.diffuse = {0.5f, 0.6f, 0.7f}, .specular = 0.3f, .shininess = 8};
	fx_quad(fx.scene, 2, 0.0, -4, 4, 0, fx_material(fx.scene, m));
	const double eye[3] = {0, -2, 5}, target[3] = {0, 0, 0}, lp[3] = {1, 2, 3};
	const double lc[3] = {1.0, 0.8, 0.6};
	fx_camera(fx.scene, eye, target, 16);
	fx_light(fx.scene, lp[0], lp[1], lp[2], lc[0], lc[1], lc[2]);
	fx_pack(&fx, RS_BVH_SAH);
	float rgb[16 * 16 * 3];
	struct rs_trace_desc desc = {.passes = 1};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &desc, rgb, NULL, NULL, NULL),
	                 RS_OK);
	for (uint32_t y = 0; y < 16; ++y) {
		for (uint32_t x = 0; x < 16; ++x) {
			struct rs_ray r;
			rs_trace_camera_ray(rs_scene_camera(fx.scene), 16, 16, x + 0.5, y + 0.5,
			                    &r);
			double t = -r.origin[2] / r.dir[2], p[3], l[3], len = 0.0;
			for (int a = 0; a < 3; ++a) {
				p[a] = r.origin[a] + t * r.dir[a];
				l[a] = lp[a] - p[a];
				len += l[a] * l[a];
			}
			assert_true(fabs(p[0]) < 4 &&
			            fabs(p[1]) < 4); /* the view is inside the quad */
			len = sqrt(len);
			double ndotl = l[2] / len;
			/* R = 2 (N.L) N - L with N = +z; V = -dir */
			double rv = -((-l[0] / len) * r.dir[0] + (-l[1] / len) * r.dir[1] +
			              (2 * ndotl - l[2] / len) * r.dir[2]);
			double spec = rv > 0 ? 0.3 * pow(rv, 8) : 0.0;
			for (int c = 0; c < 3; ++c) {
				double want =
				    0.1 * m.diffuse[c] + lc[c] * (m.diffuse[c] * ndotl + spec);
				/* float output of a double computation: 1e-6 is a few float ulps */
				assert_true(fabs(rgb[(y * 16 + x) * 3 + c] - want) < 1e-6);
			}
		}
	}
	fx_free(&fx);
}

static void light_behind_an_occluder_gives_ambient_only(void **state)
{
	for (int with_occluder = 0; with_occluder < 2; ++with_occluder) {
		struct fx fx = {.scene = fx_scene()};
		uint32_t g = fx_material(fx.scene, grey);
		fx_quad(fx.scene, 2, 0.0, -10, 10, 0, g);
		if (with_occluder)
			fx_rect(fx.scene, 2, 5.0, 2, 4, -1, 1, 1, g); /* over (3, 0, 0) */
		fx_light(fx.scene, 3, 0, 10, 1, 1, 1);
		fx_pack(&fx, RS_BVH_SAH);
		const double from[3] = {-5, 0, 5}, to[3] = {3, 0, 0};
		struct rs_trace_path p = fx_path(&fx, from, to, 1, NULL);
		assert_int_equal(p.shadow_rays, 1);
		if (with_occluder)
			for (int c = 0; c < 3; ++c)
				assert_true(fabs(p.rgb[c] - 0.1 * 0.5) < 1e-12);
		else
			assert_true(p.rgb[0] > 0.1 * 0.5 + 0.4); /* lit: + 0.5 * N.L, N.L = 1 */
		fx_free(&fx);
	}
}

static void light_below_the_surface_adds_nothing_and_casts_no_feeler(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	fx_quad(fx.scene, 2, 0.0, -10, 10, 0, fx_material(fx.scene, grey));
	fx_light(fx.scene, 0, 0, -5, 1, 1, 1);
	fx_pack(&fx, RS_BVH_SAH);
	const double from[3] = {-5, 0, 5}, to[3] = {3, 0, 0};
	struct rs_trace_path p = fx_path(&fx, from, to, 1, NULL);
	assert_int_equal(p.shadow_rays, 0);
	assert_true(fabs(p.rgb[1] - 0.05) < 1e-12);
	fx_free(&fx);
}

static void depth_is_the_distance_to_a_plane_and_infinite_on_a_miss(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	fx_quad(fx.scene, 2, 0.0, -1, 1, 0, fx_material(fx.scene, grey));
	const double eye[3] = {0, 0, 5}, target[3] = {0, 0, 0};
	fx_camera(fx.scene, eye, target, 16);
	fx_pack(&fx, RS_BVH_SAH);
	float depth[16 * 16];
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, NULL, NULL, depth, NULL, NULL),
	                 RS_OK);
	int hits = 0, misses = 0;
	for (uint32_t y = 0; y < 16; ++y) {
		for (uint32_t x = 0; x < 16; ++x) {
			struct rs_ray r;
			rs_trace_camera_ray(rs_scene_camera(fx.scene), 16, 16, x + 0.5, y + 0.5,
			                    &r);
			double t = 5.0 / -r.dir[2];
			double px = t * r.dir[0], py = t * r.dir[1];
			float d = depth[y * 16 + x];
			if (fabs(px) < 0.999 && fabs(py) < 0.999) {
				assert_true(fabs(d - t) < 1e-5 * t); /* float storage */
				hits++;
			} else if (fabs(px) > 1.001 || fabs(py) > 1.001) {
				assert_true(isinf(d) && d > 0);
				misses++;
			}
		}
	}
	assert_true(hits > 20 && misses > 20);
	fx_free(&fx);
}

static void ray_states_follow_the_paper(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	fx_quad(fx.scene, 2, 0.0, -1, 1, 0, fx_material(fx.scene, grey));
	fx_quad(fx.scene, 2, 0.0, 5, 7, 0, fx_material(fx.scene, mirror));
	fx_pack(&fx, RS_BVH_SAH);
	const double eye[3] = {0, 0, 5}, diffuse_pt[3] = {0, 0, 0}, mirror_pt[3] = {6, 6, 0};
	const double away[3] = {0, 0, 10};
	struct rs_trace_path p = fx_path(&fx, eye, away, 2, NULL);
	assert_int_equal(p.state, RS_RAY_ENVIRONMENT);
	assert_true(isinf(p.depth));
	assert_int_equal(p.segments, 1);
	p = fx_path(&fx, eye, diffuse_pt, 2, NULL);
	assert_int_equal(p.state, RS_RAY_DIFFUSE);
	assert_int_equal(p.segments, 1);
	p = fx_path(&fx, eye, mirror_pt, 1, NULL); /* pass budget spent on a mirror */
	assert_int_equal(p.state, RS_RAY_ACTIVE);
	p = fx_path(&fx, eye, mirror_pt, 3, NULL); /* reflected upwards into the environment */
	assert_int_equal(p.state, RS_RAY_ENVIRONMENT);
	assert_int_equal(p.segments, 2);
	fx_free(&fx);
}

/* A diffuse floor, a mirror box and a glass box under one light. */
static void passes_scene(struct fx *fx)
{
	fx->scene = fx_scene();
	/* glass with a little diffuse colour, so that a segment inside it still adds ambient */
	struct rs_material glass = {
	    .diffuse = {0.05f, 0.05f, 0.05f}, .transmittance = 0.9f, .ior = 1.5f};
	fx_quad(fx->scene, 1, 0.0, -6, 6, 0, fx_material(fx->scene, grey));
	const double m_lo[3] = {-3, 0, -2}, m_hi[3] = {-1, 2, 0};
	const double g_lo[3] = {1, 0, -1}, g_hi[3] = {3, 2, 1};
	fx_box(fx->scene, m_lo, m_hi, fx_material(fx->scene, mirror));
	fx_box(fx->scene, g_lo, g_hi, fx_material(fx->scene, glass));
	fx_light(fx->scene, 0, 10, 5, 1, 1, 1);
	const double eye[3] = {0, 5, 9}, target[3] = {0, 0.5, 0};
	fx_camera(fx->scene, eye, target, 24);
	fx_pack(fx, RS_BVH_SAH);
}

static void two_passes_change_only_reflective_or_refractive_pixels(void **state)
{
	struct fx fx;
	passes_scene(&fx);
	float one[24 * 24 * 3], two[24 * 24 * 3];
	struct rs_trace_desc d1 = {.passes = 1}, d2 = {.passes = 2};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d1, one, NULL, NULL, NULL), RS_OK);
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d2, two, NULL, NULL, NULL), RS_OK);
	int changed = 0, same = 0;
	for (uint32_t y = 0; y < 24; ++y) {
		for (uint32_t x = 0; x < 24; ++x) {
			struct rs_ray r;
			struct rs_trace_path p;
			rs_trace_camera_ray(rs_scene_camera(fx.scene), 24, 24, x + 0.5, y + 0.5,
			                    &r);
			assert_int_equal(
			    rs_trace_ray_path(fx.scene, &fx.packed, &d1, &r, &p, NULL, NULL),
			    RS_OK);
			const float *a = one + (y * 24 + x) * 3, *b = two + (y * 24 + x) * 3;
			if (p.state == RS_RAY_ACTIVE) {
				/* the second segment always adds light: the environment and every
				 * surface here have non-zero colour or ambient */
				assert_true(b[0] > a[0] || b[1] > a[1] || b[2] > a[2]);
				changed++;
			} else {
				assert_memory_equal(a, b, 3 * sizeof(float));
				same++;
			}
		}
	}
	assert_true(changed > 10 && same > 10);
	fx_free(&fx);
}

static void hit_numbers_count_every_test_of_every_ray(void **state)
{
	/* NONE builder: one box holding every triangle, so a ray that enters the scene box
	 * costs 1 box test and T triangle tests (T - 1 when it leaves a triangle: the skipped
	 * slot is not tested). Here T = 2 (floor) + 12 (a far box) = 14; the camera sees only
	 * floor; one light above. Per pixel: primary 1 + 14, feeler 1 + 13. */
	struct fx fx = {.scene = fx_scene()};
	uint32_t g = fx_material(fx.scene, grey);
	fx_quad(fx.scene, 2, 0.0, -100, 100, 0, g);
	const double lo[3] = {90, 90, 0.5}, hi[3] = {91, 91, 1.5};
	fx_box(fx.scene, lo, hi, g);
	fx_light(fx.scene, 0, 0, 1, 1, 1, 1);
	const double eye[3] = {0, -1, 0.8}, target[3] = {0, 0, 0};
	fx_camera(fx.scene, eye, target, 8);
	fx_pack(&fx, RS_BVH_NONE);
	struct rs_trace_stats st;
	struct rs_trace_desc desc = {.passes = 2};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &desc, NULL, NULL, &st, NULL),
	                 RS_OK);
	assert_int_equal(st.pixels, 64);
	assert_int_equal(st.rays, 64);
	assert_int_equal(st.shadow_rays, 64);
	assert_int_equal(st.box_tests, 64 * 2);
	assert_int_equal(st.triangle_tests, 64 * (14 + 13));
	assert_true(st.box_per_pixel == 2.0 && st.triangle_per_pixel == 27.0);
	assert_true(st.total_per_pixel == 29.0);
	fx_free(&fx);
}

static void hit_numbers_add_up_over_secondary_rays(void **state)
{
	/* The same counts through rs_trace_ray_path(), summed, equal the render's stats. */
	struct fx fx;
	passes_scene(&fx);
	struct rs_trace_desc desc = {.passes = 3};
	struct rs_trace_stats st;
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &desc, NULL, NULL, &st, NULL),
	                 RS_OK);
	uint64_t boxes = 0, tris = 0, rays = 0, feelers = 0;
	for (uint32_t y = 0; y < 24; ++y) {
		for (uint32_t x = 0; x < 24; ++x) {
			struct rs_ray r;
			struct rs_trace_path p;
			rs_trace_camera_ray(rs_scene_camera(fx.scene), 24, 24, x + 0.5, y + 0.5,
			                    &r);
			assert_int_equal(
			    rs_trace_ray_path(fx.scene, &fx.packed, &desc, &r, &p, NULL, NULL),
			    RS_OK);
			boxes += p.counters.box_tests;
			tris += p.counters.triangle_tests;
			rays += p.segments;
			feelers += p.shadow_rays;
		}
	}
	assert_int_equal(st.box_tests, boxes);
	assert_int_equal(st.triangle_tests, tris);
	assert_int_equal(st.rays, rays);
	assert_int_equal(st.shadow_rays, feelers);
	assert_true(st.rays > st.pixels); /* secondary rays were traced and counted */
	fx_free(&fx);
}

static void every_bvh_builder_gives_the_same_image(void **state)
{
	/* The tracer's answer must not depend on the hierarchy: the same closest triangle
	 * gives bit-identical colours. Boxes float 0.01 above the floor so that no two faces
	 * coincide (coincident faces would make ties that traversal order decides). */
	struct rs_scene *scene = fx_scene();
	struct rs_material glass = {
	    .diffuse = {0.05f, 0.05f, 0.05f}, .transmittance = 0.9f, .ior = 1.5f};
	fx_quad(scene, 1, 0.0, -6, 6, 0, fx_material(scene, grey));
	const double m_lo[3] = {-3, 0.01, -2}, m_hi[3] = {-1, 2, 0};
	const double g_lo[3] = {1, 0.01, -1}, g_hi[3] = {3, 2, 1};
	fx_box(scene, m_lo, m_hi, fx_material(scene, mirror));
	fx_box(scene, g_lo, g_hi, fx_material(scene, glass));
	fx_light(scene, 0, 10, 5, 1, 1, 1);
	const double eye[3] = {0, 5, 9}, target[3] = {0, 0.5, 0};
	fx_camera(scene, eye, target, 24);
	static float ref[24 * 24 * 3], img[24 * 24 * 3];
	const enum rs_bvh_builder builders[] = {RS_BVH_NONE, RS_BVH_LINEAR, RS_BVH_PAPER,
	                                        RS_BVH_SAH};
	struct rs_trace_desc d = {.passes = 4};
	for (int b = 0; b < 4; ++b) {
		struct fx fx = {.scene = scene};
		fx_pack(&fx, builders[b]);
		assert_int_equal(
		    rs_trace_render(scene, &fx.packed, &d, b ? img : ref, NULL, NULL, NULL), RS_OK);
		if (b)
			assert_memory_equal(ref, img, sizeof img);
		rs_pack_free(&fx.packed);
	}
	rs_scene_destroy(&scene);
}

static void row_range_writes_only_its_rows(void **state)
{
	struct fx fx;
	passes_scene(&fx);
	float full[24 * 24 * 3], part[24 * 24 * 3];
	for (size_t i = 0; i < 24 * 24 * 3; ++i)
		part[i] = -1.0f;
	struct rs_trace_desc d = {.passes = 2};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d, full, NULL, NULL, NULL), RS_OK);
	d.row_begin = 5;
	d.row_end = 9;
	struct rs_trace_stats st;
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d, part, NULL, &st, NULL), RS_OK);
	assert_int_equal(st.pixels, 4 * 24);
	for (uint32_t y = 0; y < 24; ++y) {
		const float *a = full + y * 24 * 3, *b = part + y * 24 * 3;
		if (y >= 5 && y < 9)
			assert_memory_equal(a, b, 24 * 3 * sizeof(float));
		else
			for (int i = 0; i < 24 * 3; ++i)
				assert_true(b[i] == -1.0f);
	}
	fx_free(&fx);
}

static bool half_closest(void *user, const struct rs_ray *ray, struct rs_hit *hit)
{
	return false;
}

static void bad_descriptors_are_rejected_with_a_message(void **state)
{
	struct fx fx;
	passes_scene(&fx);
	struct rs_error err;
	static const struct rs_trace_intersector half = {.closest = half_closest};
	const struct rs_trace_desc bad[] = {
	    {.intersector = &half}, {.passes = RS_TRACE_MAX_PASSES + 1},
	    {.lights = 2},          {.row_begin = 5, .row_end = 3},
	    {.row_end = 25},        {.ray_epsilon = -1.0},
	    {.ray_epsilon = NAN},   {.triangle_test = (enum rs_triangle_test)7},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
		rs_error_clear(&err);
		assert_int_equal(
		    rs_trace_render(fx.scene, &fx.packed, &bad[i], NULL, NULL, NULL, &err),
		    RS_ERR_INVALID);
		assert_true(strlen(err.message) > 0);
	}
	/* packed arrays of another scene */
	struct fx other = {.scene = fx_scene()};
	fx_quad(other.scene, 2, 0.0, -1, 1, 0, fx_material(other.scene, grey));
	fx_pack(&other, RS_BVH_NONE);
	assert_int_equal(rs_trace_render(fx.scene, &other.packed, NULL, NULL, NULL, NULL, &err),
	                 RS_ERR_INVALID);
	RS_EXPECT_CONTRACT_VIOLATION(
	    rs_trace_render(NULL, &other.packed, NULL, NULL, NULL, NULL, &err));
	struct rs_ray zero = {.tmax = INFINITY};
	struct rs_trace_path p;
	assert_int_equal(rs_trace_ray_path(fx.scene, &fx.packed, NULL, &zero, &p, NULL, &err),
	                 RS_ERR_INVALID);
	fx_free(&other);
	fx_free(&fx);
}

static void empty_scene_shows_the_environment(void **state)
{
	struct fx fx = {.scene = fx_scene()};
	struct rs_environment env = {.half_size = 10};
	for (int f = 0; f < 6; ++f)
		for (int c = 0; c < 3; ++c)
			env.face_color[f][c] = 0.5f;
	assert_int_equal(rs_scene_set_environment(fx.scene, &env, NULL), RS_OK);
	assert_int_equal(rs_pack_layout(NULL, 0, 0, 0, &fx.packed, NULL), RS_OK);
	assert_int_equal(rs_pack_alloc(&fx.packed, NULL), RS_OK);
	float rgb[8 * 8 * 3], depth[8 * 8];
	struct rs_trace_desc d = {.width = 8, .height = 8};
	assert_int_equal(rs_trace_render(fx.scene, &fx.packed, &d, rgb, depth, NULL, NULL), RS_OK);
	for (int i = 0; i < 64; ++i) {
		assert_true(isinf(depth[i]));
		/* grid lines (0.25 x) or face colour */
		assert_true(rgb[i * 3] == 0.5f || rgb[i * 3] == 0.125f);
	}
	fx_free(&fx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(lit_plane_matches_the_phong_formula),
	    cmocka_unit_test(light_behind_an_occluder_gives_ambient_only),
	    cmocka_unit_test(light_below_the_surface_adds_nothing_and_casts_no_feeler),
	    cmocka_unit_test(depth_is_the_distance_to_a_plane_and_infinite_on_a_miss),
	    cmocka_unit_test(ray_states_follow_the_paper),
	    cmocka_unit_test(two_passes_change_only_reflective_or_refractive_pixels),
	    cmocka_unit_test(hit_numbers_count_every_test_of_every_ray),
	    cmocka_unit_test(hit_numbers_add_up_over_secondary_rays),
	    cmocka_unit_test(every_bvh_builder_gives_the_same_image),
	    cmocka_unit_test(row_range_writes_only_its_rows),
	    cmocka_unit_test(bad_descriptors_are_rejected_with_a_message),
	    cmocka_unit_test(empty_scene_shows_the_environment),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
