/* Rasterized primary hits (paper 3.2.1) against traced ones: the same triangle on at least
 * 99.9% of the covered pixels, and the image against the CPU reference as in
 * test_gl_accuracy; also at a sub-pixel sample of still-pose refinement (rs_camera.sample:
 * u_jitter in the kernels, folded into the raster pass's lens shift). EGL (llvmpipe in
 * CI); skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 128u

static void ids(enum rs_primary_mode primary, const struct rs_scene *scene, uint32_t sample,
                uint32_t *out, float *rgb)
{
	struct rs_camera cam = *rs_scene_camera(scene);
	cam.sample = sample;
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .lights = 4, .primary = primary};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
	struct rs_frame frame = {.rgb = rgb, .triangle = out};
	assert_int_equal(rs_renderer_render(r, &cam, &frame, NULL), RS_OK);
	const struct rs_render_stats *s = rs_renderer_stats(r);
	bool rasterized = false; /* the frame ran the raster pass */
	for (uint32_t k = 0; k < s->kernel_count; ++k)
		rasterized |= strcmp(s->kernels[k].name, "raster") == 0;
	assert_int_equal(rasterized, primary == RS_PRIMARY_RASTER);
	rs_renderer_destroy(&r);
}

static void agree(const char *name, uint32_t sample)
{
	struct rs_scene *scene = gl_scene(name);
	static uint32_t traced[SIZE * SIZE], rastered[SIZE * SIZE], cpu_ids[SIZE * SIZE];
	static float rgb[SIZE * SIZE * 3], want[SIZE * SIZE * 3];
	ids(RS_PRIMARY_TRACE, scene, sample, traced, rgb);
	ids(RS_PRIMARY_RASTER, scene, sample, rastered, rgb);
	struct rs_camera cam = *rs_scene_camera(scene);
	cam.sample = sample;
	size_t covered = 0, same = 0;
	for (size_t i = 0; i < SIZE * SIZE; ++i) {
		if (traced[i] == RS_NO_SLOT && rastered[i] == RS_NO_SLOT)
			continue;
		covered++;
		same += traced[i] == rastered[i];
	}
	/* the CPU backend names the same triangles as the traced GL primary */
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 2, .lights = 4};
	struct rs_renderer *cpu = NULL;
	assert_int_equal(rs_renderer_create_cpu(&desc, &cpu, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(cpu, scene, NULL), RS_OK);
	struct rs_frame frame = {.rgb = want, .triangle = cpu_ids};
	assert_int_equal(rs_renderer_render(cpu, &cam, &frame, NULL), RS_OK);
	size_t cpu_same = 0;
	for (size_t i = 0; i < SIZE * SIZE; ++i)
		cpu_same += cpu_ids[i] == traced[i];
	struct rs_image_diff diff;
	rs_image_compare(rgb, want, SIZE, SIZE, 3, 1.0, 8.0 / 255.0, &diff);
	print_message("%s: raster = traced on %zu of %zu covered pixels (%.3f%%); traced GL = "
	              "CPU on %zu of %d; raster image PSNR %.2f dB, %.3f%% off by > 8/255\n",
	              name, same, covered, 100.0 * (double)same / (double)covered, cpu_same,
	              SIZE * SIZE, diff.psnr_db, 100.0 * diff.bad_share);
	assert_true(covered > SIZE * SIZE / 10);
	assert_true((double)same >= 0.999 * (double)covered);
	assert_true((double)cpu_same >= 0.999 * SIZE * SIZE);
	assert_true(diff.psnr_db >= 44.0); /* reached: 45.9 (Cow1) to 137 dB (Box) */
	assert_true(diff.bad_share <= 0.0005);
	rs_renderer_destroy(&cpu);
	rs_scene_destroy(&scene);
}

static void raster_and_traced_primaries_agree_on_box(void **state)
{
	agree("box", 0);
}
static void raster_and_traced_primaries_agree_on_cow1(void **state)
{
	agree("cow1", 0);
}
static void raster_and_traced_primaries_agree_on_cow5(void **state)
{
	agree("cow5", 0);
}

/* Sample 5 moves every primary ray by (-0.23, -0.15) pixels: the traced and rasterized GL
 * primaries and the CPU's still agree, and the image is not sample 0's (the offset is
 * applied, not dropped on the way). */
static void primaries_agree_at_a_subpixel_sample_on_cow1(void **state)
{
	agree("cow1", 5);
	struct rs_scene *scene = gl_scene("cow1");
	static uint32_t at0[SIZE * SIZE], at5[SIZE * SIZE];
	static float rgb[SIZE * SIZE * 3];
	ids(RS_PRIMARY_RASTER, scene, 0, at0, rgb);
	ids(RS_PRIMARY_RASTER, scene, 5, at5, rgb);
	size_t moved = 0;
	for (size_t i = 0; i < SIZE * SIZE; ++i)
		moved += at0[i] != at5[i];
	print_message("cow1: %zu pixels see another triangle at sample 5\n", moved);
	assert_true(moved > 0);
	rs_scene_destroy(&scene);
}

static void raster_counters_count_no_primary_traversal(void **state)
{
	struct rs_render_desc desc = {.width = 32, .height = 32, .counters = true};
	struct rs_scene *scene = gl_scene("box");
	static float rgb[32 * 32 * 3];
	struct rs_renderer *r = gl_open("egl", &desc), *cpu = NULL;
	if (!r)
		gl_skip();
	gl_render(r, scene, rgb, NULL);
	uint64_t traced_boxes = rs_renderer_stats(r)->box_tests;
	rs_renderer_destroy(&r);
	desc.primary = RS_PRIMARY_RASTER;
	r = gl_open("egl", &desc);
	gl_render(r, scene, rgb, NULL);
	desc.primary = RS_PRIMARY_TRACE;
	assert_int_equal(rs_renderer_create_cpu(&desc, &cpu, NULL), RS_OK);
	gl_render(cpu, scene, rgb, NULL);
	const struct rs_render_stats *g = rs_renderer_stats(r), *c = rs_renderer_stats(cpu);
	assert_int_equal(g->primary_rays, 32 * 32);
	assert_int_equal(g->secondary_rays, c->secondary_rays);
	assert_int_equal(g->shadow_rays, c->shadow_rays);
	assert_true(g->box_tests < traced_boxes); /* feelers and secondary rays only */
	rs_renderer_destroy(&cpu);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(raster_and_traced_primaries_agree_on_box),
	    cmocka_unit_test(raster_and_traced_primaries_agree_on_cow1),
	    cmocka_unit_test(raster_and_traced_primaries_agree_on_cow5),
	    cmocka_unit_test(primaries_agree_at_a_subpixel_sample_on_cow1),
	    cmocka_unit_test(raster_counters_count_no_primary_traversal),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
