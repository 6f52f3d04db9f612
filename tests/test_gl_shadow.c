/* Cube shadow maps with a box filter against exact shadow feelers (the CPU reference):
 * the error of a few map settings on Box and Cow1, bars just under what llvmpipe reaches
 * (docs/gles.md has the full table); no feelers are cast in map mode; the box filter is
 * seamless across cube faces (a shadow edge on a seam, built here). shadows=none against
 * the reference without feelers, on every chain, and its counted frames cast none. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 128u

static void map_error(const char *name, uint32_t map, uint32_t filter, double psnr_min,
                      double bad_max)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .lights = 4,
	                              .shadows = RS_SHADOW_MAP,
	                              .shadow_map_size = map,
	                              .shadow_filter = filter,
	                              .counters = true};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	struct rs_scene *scene = gl_scene(name);
	static float got[SIZE * SIZE * 3], want[SIZE * SIZE * 3];
	gl_render(r, scene, got, NULL);
	assert_int_equal(rs_renderer_stats(r)->shadow_rays, 0);
	desc.shadows = RS_SHADOW_RAYS;
	gl_reference(&desc, scene, want, NULL);
	/* Compared as displayed (clamped to [0, 1]): with 4 lights most lit pixels exceed 1,
	 * where a light more or less changes nothing on screen. */
	for (size_t i = 0; i < SIZE * SIZE * 3; ++i) {
		got[i] = fminf(fmaxf(got[i], 0.0f), 1.0f);
		want[i] = fminf(fmaxf(want[i], 0.0f), 1.0f);
	}
	struct rs_image_diff diff;
	rs_image_compare(got, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &diff);
	print_message("%s map %u filter %u: PSNR %.2f dB, %.3f%% pixels off by > 8/255\n", name,
	              map, filter, diff.psnr_db, 100.0 * diff.bad_share);
	assert_true(diff.psnr_db >= psnr_min);
	assert_true(diff.bad_share <= bad_max);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static void box_map_1024_unfiltered(void **state)
{
	map_error("box", 1024, 1, 40.0, 0.001);
}
static void box_map_512_box3(void **state)
{
	map_error("box", 512, 3, 36.0, 0.007);
}
static void cow1_map_1024_unfiltered(void **state)
{
	map_error("cow1", 1024, 1, 36.0, 0.007);
}
static void cow1_map_256_box5(void **state)
{
	map_error("cow1", 256, 5, 27.5, 0.06);
}

/* shadows=none on `chain`: every light in front of a surface lit, no feeler cast, as the
 * CPU reference renders it without feelers (>= 57 dB, fp32 against double), and not the
 * shadowed image (Cow1's lights cast shadows, so a kernel that kept its feelers fails). */
static void unshadowed(enum rs_kernel_chain chain)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 4,
	                              .chain = chain,
	                              .shadows = RS_SHADOW_NONE};
	struct rs_scene *scene = gl_scene("cow1");
	static float got[SIZE * SIZE * 3], want[SIZE * SIZE * 3], shadowed[SIZE * SIZE * 3];
	if (!gl_frame("egl", &desc, scene, got, NULL, NULL))
		gl_skip();
	gl_reference(&desc, scene, want, NULL);
	desc.shadows = RS_SHADOW_RAYS;
	gl_reference(&desc, scene, shadowed, NULL);
	struct rs_image_diff diff, lost;
	rs_image_compare(got, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &diff);
	rs_image_compare(shadowed, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &lost);
	print_message("none, chain %d: PSNR %.2f dB, %.4f%% pixels off by > 8/255, max %.4f; "
	              "against the shadowed reference %.2f dB\n",
	              (int)chain, diff.psnr_db, 100.0 * diff.bad_share, diff.max_abs_error,
	              lost.psnr_db);
	assert_true(diff.psnr_db >= 57.0);
	assert_true(diff.bad_share <= 0.0005);
	assert_true(lost.psnr_db < 40.0 && lost.bad_share > 0.01);
	rs_scene_destroy(&scene);
}

static void unshadowed_fused(void **state)
{
	unshadowed(RS_CHAIN_FUSED);
}
static void unshadowed_separate(void **state)
{
	unshadowed(RS_CHAIN_SEPARATE);
}
static void unshadowed_paper(void **state)
{
	unshadowed(RS_CHAIN_PAPER);
}

/* Counted frames cast no feeler with shadows=none, on the CPU reference and on GL for
 * traced primaries and Table 3's classic column (raster primaries, environment map); the
 * same frames with feelers count some, so the count is live. */
static void unshadowed_counts_no_feelers(void **state)
{
	struct rs_scene *scene = gl_scene("cow1");
	static float rgb[SIZE * SIZE * 3];
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 4,
	                              .counters = true,
	                              .shadows = RS_SHADOW_NONE};
	struct rs_renderer *cpu = NULL;
	struct rs_error err;
	for (int shadows = 0; shadows < 2; ++shadows) {
		desc.shadows = shadows ? RS_SHADOW_RAYS : RS_SHADOW_NONE;
		if (rs_renderer_create_cpu(&desc, &cpu, &err) != RS_OK)
			fail_msg("cpu: %s", err.message);
		gl_render(cpu, scene, rgb, NULL);
		const struct rs_render_stats *cs = rs_renderer_stats(cpu);
		assert_true(cs->secondary_rays > 0);
		assert_true(shadows ? cs->shadow_rays > 0 : cs->shadow_rays == 0);
		rs_renderer_destroy(&cpu);
	}
	static const enum rs_primary_mode primaries[] = {RS_PRIMARY_TRACE, RS_PRIMARY_RASTER};
	static const enum rs_reflection_mode reflections[] = {RS_REFLECT_TRACE, RS_REFLECT_ENVMAP};
	for (int k = 0; k < 2; ++k)
		for (int shadows = 0; shadows < 2; ++shadows) {
			desc.primary = primaries[k];
			desc.reflections = reflections[k];
			desc.shadows = shadows ? RS_SHADOW_RAYS : RS_SHADOW_NONE;
			struct rs_render_stats st;
			if (!gl_frame("egl", &desc, scene, rgb, NULL, &st))
				gl_skip();
			assert_true(st.counters_valid && st.secondary_rays > 0);
			print_message("%s, shadows %s: %llu shadow rays\n",
			              k ? "raster envmap" : "trace", shadows ? "rays" : "none",
			              (unsigned long long)st.shadow_rays);
			assert_true(shadows ? st.shadow_rays > 0 : st.shadow_rays == 0);
		}
	rs_scene_destroy(&scene);
}

/* A shadow edge on a cube-face seam. A point light at the origin over a floor at y = -1
 * (x 0.25..1.6, z -0.8..0.8): face -y sees the floor where x < 1, face +x beyond, so the
 * seam on the floor is the line x = 1. An occluder strip at y = -0.5 shadows the floor
 * between x = 0.5 + K z and x = 1 + K z: its right edge crosses the seam at z = 0 at a
 * shallow angle (within 0.04 of it, under a texel of a 32-texel map, over the whole
 * floor), its left edge runs parallel in the middle of face -y. The floor is three strips
 * (triangles 0-1: x 0.25..0.75 around the edge away from the seam, 2-3: 0.75..1.25 around
 * the edge on the seam, 4-5: the rest), so a pixel's primary triangle says its band. */
#define SEAM_K 0.05

/* Quad (corners 0..3 in order, double xyz) of material `m`: two triangles. */
static void add_quad(struct rs_scene *s, const double pos[12], uint32_t m)
{
	static const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
	struct rs_mesh_desc mesh = {.positions_f64 = pos,
	                            .vertex_count = 4,
	                            .indices = idx,
	                            .triangle_count = 2,
	                            .material = m};
	assert_int_equal(rs_scene_add_mesh(s, &mesh, NULL), RS_OK);
}

static struct rs_scene *seam_scene(bool occluder)
{
	struct rs_scene *s = NULL;
	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	struct rs_material white = {.diffuse = {1.0f, 1.0f, 1.0f}};
	uint32_t m;
	assert_int_equal(rs_scene_add_material(s, &white, &m, NULL), RS_OK);
	static const double xs[4] = {0.25, 0.75, 1.25, 1.6};
	for (int b = 0; b < 3; ++b) {
		const double pos[12] = {xs[b],     -1, -0.8, xs[b + 1], -1, -0.8,
		                        xs[b + 1], -1, 0.8,  xs[b],     -1, 0.8};
		add_quad(s, pos, m);
	}
	if (occluder) { /* the floor edge x = c + K z seen from the light at y = -0.5 */
		const double pos[12] = {
		    0.25 - 0.5 * SEAM_K, -0.5, -0.5, 0.5 - 0.5 * SEAM_K,  -0.5, -0.5,
		    0.5 + 0.5 * SEAM_K,  -0.5, 0.5,  0.25 + 0.5 * SEAM_K, -0.5, 0.5};
		add_quad(s, pos, m);
	}
	struct rs_light light = {.position = {0, 0, 0}, .color = {1, 1, 1}};
	assert_int_equal(rs_scene_add_light(s, &light, NULL), RS_OK);
	assert_int_equal(rs_scene_set_ambient(s, 0.0, NULL), RS_OK);
	/* From the +x side, above: no line of sight to the floor passes the occluder. */
	struct rs_camera cam = {.eye = {3.2, 0.9, 0.0},
	                        .target = {0.9, -1.0, 0.0},
	                        .up = {0, 1, 0},
	                        .fov_y_deg = 34.0,
	                        .width = SIZE,
	                        .height = SIZE};
	assert_int_equal(rs_scene_set_camera(s, &cam, NULL), RS_OK);
	return s;
}

/* Mean visibility error |map - exact| of the floor pixels of band b (0: the edge away from
 * the seam, 1: the edge on it), in units of the pixel's unshadowed radiance. */
static void seam_errors(const float *map, const float *exact, const float *open,
                        const uint32_t *tri, double out[2])
{
	double sum[2] = {0, 0};
	size_t n[2] = {0, 0};
	for (size_t i = 0; i < SIZE * SIZE; ++i) {
		uint32_t b = tri[i] / 2;
		if (tri[i] == RS_NO_SLOT || b > 1 || !(open[3 * i] > 1e-3f))
			continue;
		sum[b] += fabs((double)map[3 * i] - (double)exact[3 * i]) / open[3 * i];
		n[b]++;
	}
	assert_true(n[0] > 300 && n[1] > 300);
	out[0] = sum[0] / (double)n[0];
	out[1] = sum[1] / (double)n[1];
}

static void seam_filter(uint32_t filter)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 1,
	                              .shadows = RS_SHADOW_MAP,
	                              .shadow_map_size = 32,
	                              .shadow_filter = filter};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	struct rs_scene *scene = seam_scene(true), *open_scene = seam_scene(false);
	static float map[SIZE * SIZE * 3], exact[SIZE * SIZE * 3], open[SIZE * SIZE * 3];
	static uint32_t tri[SIZE * SIZE];
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_OK);
	struct rs_frame frame = {.rgb = map, .triangle = tri};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
	rs_renderer_destroy(&r);
	desc.shadows = RS_SHADOW_RAYS;
	gl_reference(&desc, scene, exact, NULL);
	gl_reference(&desc, open_scene, open, NULL);
	double e[2];
	seam_errors(map, exact, open, tri, e);
	print_message("filter %u: visibility error %.4f away from the seam, %.4f on it\n", filter,
	              e[0], e[1]);
	/* No worse on the seam than away from it, within 25 %: beyond the seam the floor is on
	 * face +x, whose texels there are up to 1.6x wider on the floor than face -y's (x^2),
	 * so that edge's penumbra is a little wider (measured 1.18x with filter 3, 1.12x with
	 * 5). And not better by more than 20 %: clamping the box to one face dropped the
	 * penumbra on the seam (0.58x and 0.36x of the error away from it), a visible seam. */
	assert_true(e[1] > 0.0 && e[0] > 0.0);
	assert_true(e[1] <= 1.25 * e[0]);
	assert_true(e[1] >= 0.8 * e[0]);
	rs_scene_destroy(&scene);
	rs_scene_destroy(&open_scene);
}

static void shadow_map_filter_3_is_seamless(void **state)
{
	seam_filter(3);
}
static void shadow_map_filter_5_is_seamless(void **state)
{
	seam_filter(5);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(box_map_1024_unfiltered),
	    cmocka_unit_test(box_map_512_box3),
	    cmocka_unit_test(cow1_map_1024_unfiltered),
	    cmocka_unit_test(cow1_map_256_box5),
	    cmocka_unit_test(shadow_map_filter_3_is_seamless),
	    cmocka_unit_test(shadow_map_filter_5_is_seamless),
	    cmocka_unit_test(unshadowed_fused),
	    cmocka_unit_test(unshadowed_separate),
	    cmocka_unit_test(unshadowed_paper),
	    cmocka_unit_test(unshadowed_counts_no_feelers),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
