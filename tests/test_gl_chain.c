/* The GL kernel chain beyond the image: GPU hit counters against the CPU's (same BVH,
 * within 0.1%; with both slab ends widened (docs/tracer.md R3) they agree exactly on Box
 * and to 0.005% on Cow1: what is left is fp32 against double at grazing box tests), fused
 * and separate chains alike, the paper's chain (environment, shading and next ray apart)
 * against the fused one, RGBA8 as rs_image_quantize() rounds, per-frame cameras, per-kernel
 * timings. EGL (llvmpipe in CI); skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 64u

static double rel(uint64_t a, uint64_t b)
{
	double d = (double)a - (double)b;
	return fabs(d) / (b ? (double)b : 1.0);
}

static void counters_match(const char *name)
{
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .lights = 4, .counters = true};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	struct rs_scene *scene = gl_scene(name);
	static float rgb[SIZE * SIZE * 3];
	gl_render(r, scene, rgb, NULL);
	struct rs_renderer *cpu = NULL;
	assert_int_equal(rs_renderer_create_cpu(&desc, &cpu, NULL), RS_OK);
	gl_render(cpu, scene, rgb, NULL);
	const struct rs_render_stats *g = rs_renderer_stats(r), *c = rs_renderer_stats(cpu);
	print_message("%s: boxes %llu / %llu, triangles %llu / %llu, shadow %llu / %llu, "
	              "secondary %llu / %llu\n",
	              name, (unsigned long long)g->box_tests, (unsigned long long)c->box_tests,
	              (unsigned long long)g->triangle_tests, (unsigned long long)c->triangle_tests,
	              (unsigned long long)g->shadow_rays, (unsigned long long)c->shadow_rays,
	              (unsigned long long)g->secondary_rays, (unsigned long long)c->secondary_rays);
	assert_true(g->counters_valid);
	assert_true(c->box_tests > 0 && c->triangle_tests > 0);
	assert_true(rel(g->box_tests, c->box_tests) <= 0.001);
	assert_true(rel(g->triangle_tests, c->triangle_tests) <= 0.001);
	assert_true(rel(g->box_tests + g->triangle_tests, c->box_tests + c->triangle_tests) <=
	            0.001);
	assert_true(rel(g->shadow_rays, c->shadow_rays) <= 0.001);
	assert_true(rel(g->secondary_rays, c->secondary_rays) <= 0.001);
	assert_int_equal(g->primary_rays, SIZE * SIZE);
	rs_renderer_destroy(&cpu);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static void gpu_counters_equal_the_cpu_reference_on_box(void **state)
{
	counters_match("box");
}
static void gpu_counters_equal_the_cpu_reference_on_cow1(void **state)
{
	counters_match("cow1");
}

static void fused_and_separate_chains_render_alike(void **state)
{
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 3};
	struct rs_scene *scene = gl_scene("box");
	static float a[SIZE * SIZE * 3], b[SIZE * SIZE * 3], da[SIZE * SIZE], db[SIZE * SIZE];
	desc.chain = RS_CHAIN_SEPARATE;
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	gl_render(r, scene, a, da);
	const struct rs_render_stats *s = rs_renderer_stats(r);
	assert_true(s->kernel_count >= 3);
	assert_string_equal(s->kernels[0].name, "raygen");
	assert_string_equal(s->kernels[1].name, "intersect");
	assert_int_equal(s->kernels[1].calls, 3);
	assert_false(s->counters_valid);
	rs_renderer_destroy(&r);
	desc.chain = RS_CHAIN_FUSED;
	r = gl_open("egl", &desc);
	gl_render(r, scene, b, db);
	s = rs_renderer_stats(r);
	/* the fused chain's first pass makes its own primary rays: no raygen pass */
	assert_string_equal(s->kernels[0].name, "trace");
	assert_int_equal(s->kernels[0].calls, 3);
	struct rs_image_diff diff;
	rs_image_compare(b, a, SIZE, SIZE, 3, 1.0, 1e-5, &diff);
	assert_true(diff.max_abs_error <= 1e-5);
	rs_image_compare(db, da, SIZE, SIZE, 1, 1.0, 1e-5, &diff);
	assert_int_equal(diff.mismatched, 0);
	assert_true(diff.max_abs_error <= 1e-5);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static bool chain_frame(const struct rs_render_desc *desc, const struct rs_scene *scene, float *rgb,
                        float *depth, struct rs_render_stats *stats)
{
	return gl_frame("egl", desc, scene, rgb, depth, stats);
}

/* The paper's chain (environment, shading and next ray each a pass) against the fused one:
 * the same fp32 functions on the same values, the state kept in RGBA32F between passes, so
 * the images agree to float rounding (tolerance 1e-5 of linear colour; measured 0 on
 * llvmpipe) and the depths exactly. */
static void paper_chain_matches_fused(const char *name, enum rs_shadow_mode shadows,
                                      enum rs_primary_mode primary)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 2,
	                              .primary = primary,
	                              .shadows = shadows,
	                              .shadow_map_size = 256,
	                              .shadow_filter = 3};
	struct rs_scene *scene = gl_scene(name);
	static float a[SIZE * SIZE * 3], b[SIZE * SIZE * 3], da[SIZE * SIZE], db[SIZE * SIZE];
	struct rs_render_stats sa, sb;
	desc.chain = RS_CHAIN_PAPER;
	if (!chain_frame(&desc, scene, a, da, &sa))
		gl_skip();
	static const char *const names[] = {"raygen", "intersect", "environment", "shading",
	                                    "next ray"};
	for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
		const struct rs_render_kernel_time *t = gl_kernel(&sa, names[k]);
		assert_non_null(t);
		if (k == 1 && primary == RS_PRIMARY_RASTER) {
			assert_non_null(gl_kernel(&sa, "raster"));
			assert_int_equal(gl_kernel(&sa, "raster")->calls, 1);
			assert_int_equal(t->calls, desc.passes - 1);
			continue;
		}
		assert_int_equal(t->calls, k == 0 ? 1 : desc.passes);
	}
	assert_null(gl_kernel(&sa, "trace"));
	assert_null(gl_kernel(&sa, "shade"));
	desc.chain = RS_CHAIN_FUSED;
	assert_true(chain_frame(&desc, scene, b, db, &sb));
	assert_non_null(gl_kernel(&sb, "trace"));
	struct rs_image_diff diff;
	rs_image_compare(a, b, SIZE, SIZE, 3, 1.0, 1e-5, &diff);
	print_message("%s %s %s: paper vs fused max |diff| %g\n", name,
	              shadows == RS_SHADOW_MAP ? "map" : "rays",
	              primary == RS_PRIMARY_RASTER ? "raster" : "traced", diff.max_abs_error);
	assert_true(diff.max_abs_error <= 1e-5);
	rs_image_compare(da, db, SIZE, SIZE, 1, 1.0, 0.0, &diff);
	assert_int_equal(diff.mismatched, 0);
	assert_true(diff.max_abs_error == 0.0);
	/* and the picture is not empty: something was lit */
	double sum = 0.0;
	for (size_t i = 0; i < SIZE * SIZE * 3; ++i)
		sum += a[i];
	assert_true(sum > 0.01 * SIZE * SIZE);
	rs_scene_destroy(&scene);
}

static void paper_chain_renders_box_as_fused_with_shadow_rays(void **state)
{
	paper_chain_matches_fused("box", RS_SHADOW_RAYS, RS_PRIMARY_TRACE);
}
static void paper_chain_renders_cow1_as_fused_with_shadow_rays(void **state)
{
	paper_chain_matches_fused("cow1", RS_SHADOW_RAYS, RS_PRIMARY_TRACE);
}
static void paper_chain_renders_box_as_fused_with_shadow_maps(void **state)
{
	paper_chain_matches_fused("box", RS_SHADOW_MAP, RS_PRIMARY_TRACE);
}
static void paper_chain_renders_cow1_as_fused_with_shadow_maps(void **state)
{
	paper_chain_matches_fused("cow1", RS_SHADOW_MAP, RS_PRIMARY_TRACE);
}
/* The raster pass stands in for the first intersection kernel in either chain. */
static void paper_chain_renders_cow1_as_fused_with_raster_primary(void **state)
{
	paper_chain_matches_fused("cow1", RS_SHADOW_RAYS, RS_PRIMARY_RASTER);
}

/* With counters the paper's chain counts what the separate chain counts, exactly (the same
 * traversals), and its image is the fused chain's. */
static void paper_chain_counts_as_the_separate_chain(const char *name)
{
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .lights = 2, .counters = true};
	struct rs_scene *scene = gl_scene(name);
	static float a[SIZE * SIZE * 3], b[SIZE * SIZE * 3], f[SIZE * SIZE * 3];
	static float da[SIZE * SIZE], db[SIZE * SIZE];
	/* zeroed: gcc -O3 -Werror sees maybe-uninitialized through the skip path */
	struct rs_render_stats sa = {0}, sb = {0}, sf = {0};
	desc.chain = RS_CHAIN_PAPER;
	if (!chain_frame(&desc, scene, a, da, &sa))
		gl_skip();
	desc.chain = RS_CHAIN_SEPARATE;
	assert_true(chain_frame(&desc, scene, b, db, &sb));
	assert_true(sa.counters_valid && sb.counters_valid);
	assert_true(sa.box_tests > 0 && sa.shadow_rays > 0);
	assert_int_equal(sa.box_tests, sb.box_tests);
	assert_int_equal(sa.triangle_tests, sb.triangle_tests);
	assert_int_equal(sa.shadow_rays, sb.shadow_rays);
	assert_int_equal(sa.secondary_rays, sb.secondary_rays);
	desc.chain = RS_CHAIN_FUSED;
	desc.counters = false;
	assert_true(chain_frame(&desc, scene, f, db, &sf));
	struct rs_image_diff diff;
	rs_image_compare(a, f, SIZE, SIZE, 3, 1.0, 1e-5, &diff);
	assert_true(diff.max_abs_error <= 1e-5);
	rs_scene_destroy(&scene);
}

static void paper_chain_counts_box_as_the_separate_chain(void **state)
{
	paper_chain_counts_as_the_separate_chain("box");
}
static void paper_chain_counts_cow1_as_the_separate_chain(void **state)
{
	paper_chain_counts_as_the_separate_chain("cow1");
}

/* Environment mapping switches tracing off from the second pass on, in the intersection
 * kernel, and reads the map in the environment kernel: the paper's chain gives the
 * separate chain's image (the fused chain's, one pass that reads the map at its end, is
 * test_gl_envmap's). */
static void paper_chain_renders_environment_maps_as_the_separate_chain(void **state)
{
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 3,
	                              .lights = 2,
	                              .reflections = RS_REFLECT_ENVMAP};
	struct rs_scene *scene = gl_scene("cow1");
	static float a[SIZE * SIZE * 3], b[SIZE * SIZE * 3], t[SIZE * SIZE * 3];
	static float da[SIZE * SIZE], db[SIZE * SIZE];
	struct rs_render_stats sa, sb;
	desc.chain = RS_CHAIN_PAPER;
	if (!chain_frame(&desc, scene, a, da, &sa))
		gl_skip();
	assert_int_equal(gl_kernel(&sa, "environment")->calls, 2);
	desc.chain = RS_CHAIN_SEPARATE;
	assert_true(chain_frame(&desc, scene, b, db, &sb));
	struct rs_image_diff diff;
	rs_image_compare(a, b, SIZE, SIZE, 3, 1.0, 1e-5, &diff);
	assert_true(diff.max_abs_error <= 1e-5);
	/* and the map was read: tracing the reflections gives another picture */
	desc.reflections = RS_REFLECT_TRACE;
	assert_true(chain_frame(&desc, scene, t, db, &sb));
	rs_image_compare(a, t, SIZE, SIZE, 3, 1.0, 1e-5, &diff);
	assert_true(diff.max_abs_error > 1e-3);
	rs_scene_destroy(&scene);
}

/* The same kernels on OSMesa's desktop GL context (#version 300 es through
 * ARB_ES3_compatibility): the paper's chain there gives EGL's fused image. */
static void paper_chain_on_osmesa_renders_as_fused_on_egl(void **state)
{
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .lights = 2, .chain = RS_CHAIN_PAPER};
	struct rs_scene *scene = gl_scene("cow1");
	static float a[SIZE * SIZE * 3], b[SIZE * SIZE * 3];
	struct rs_render_stats sa, sb;
	if (!gl_frame("osmesa", &desc, scene, a, NULL, &sa)) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	assert_int_equal(gl_kernel(&sa, "next ray")->calls, 2);
	desc.chain = RS_CHAIN_FUSED;
	if (!chain_frame(&desc, scene, b, NULL, &sb)) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	struct rs_image_diff diff;
	rs_image_compare(a, b, SIZE, SIZE, 3, 1.0, 1e-5, &diff);
	assert_true(diff.max_abs_error <= 1e-5);
	rs_scene_destroy(&scene);
}

static void rgba8_is_the_quantized_colour(void **state)
{
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	struct rs_scene *scene = gl_scene("box");
	static float rgb[SIZE * SIZE * 3];
	static uint8_t got[SIZE * SIZE * 4], want[SIZE * SIZE * 3];
	assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
	struct rs_frame frame = {.rgb = rgb, .rgba8 = got};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, NULL), RS_OK);
	rs_image_quantize(rgb, SIZE, SIZE, want);
	for (size_t i = 0; i < SIZE * SIZE; ++i) {
		for (int c = 0; c < 3; ++c)
			assert_int_equal(got[4 * i + c], want[3 * i + c]);
		assert_int_equal(got[4 * i + 3], 255);
	}
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static void a_per_frame_camera_renders_as_the_cpu_does(void **state)
{
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .lights = 2};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	struct rs_scene *scene = gl_scene("cow1");
	struct rs_camera cam = *rs_scene_camera(scene);
	cam.eye[0] += 0.3 * (cam.target[2] - cam.eye[2]);
	cam.fov_y_deg = 35.0;
	cam.shift[0] = 0.1;
	static float got[SIZE * SIZE * 3], want[SIZE * SIZE * 3];
	assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
	struct rs_frame frame = {.rgb = got};
	assert_int_equal(rs_renderer_render(r, &cam, &frame, NULL), RS_OK);
	struct rs_renderer *cpu = NULL;
	assert_int_equal(rs_renderer_create_cpu(&desc, &cpu, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(cpu, scene, NULL), RS_OK);
	frame.rgb = want;
	assert_int_equal(rs_renderer_render(cpu, &cam, &frame, NULL), RS_OK);
	struct rs_image_diff diff;
	rs_image_compare(got, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &diff);
	assert_true(diff.psnr_db >= 40.0);
	/* and it is a different picture from the scene camera's */
	frame.rgb = want;
	assert_int_equal(rs_renderer_render(cpu, NULL, &frame, NULL), RS_OK);
	rs_image_compare(got, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &diff);
	assert_true(diff.psnr_db < 30.0);
	rs_renderer_destroy(&cpu);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(gpu_counters_equal_the_cpu_reference_on_box),
	    cmocka_unit_test(gpu_counters_equal_the_cpu_reference_on_cow1),
	    cmocka_unit_test(fused_and_separate_chains_render_alike),
	    cmocka_unit_test(paper_chain_renders_box_as_fused_with_shadow_rays),
	    cmocka_unit_test(paper_chain_renders_cow1_as_fused_with_shadow_rays),
	    cmocka_unit_test(paper_chain_renders_box_as_fused_with_shadow_maps),
	    cmocka_unit_test(paper_chain_renders_cow1_as_fused_with_shadow_maps),
	    cmocka_unit_test(paper_chain_renders_cow1_as_fused_with_raster_primary),
	    cmocka_unit_test(paper_chain_counts_box_as_the_separate_chain),
	    cmocka_unit_test(paper_chain_counts_cow1_as_the_separate_chain),
	    cmocka_unit_test(paper_chain_renders_environment_maps_as_the_separate_chain),
	    cmocka_unit_test(paper_chain_on_osmesa_renders_as_fused_on_egl),
	    cmocka_unit_test(rgba8_is_the_quantized_colour),
	    cmocka_unit_test(a_per_frame_camera_renders_as_the_cpu_does),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
