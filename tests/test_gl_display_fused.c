/* The display pass fused into the last trace pass (docs/gles.md, "The plan"): a frame on the
 * fused chain that asks for RGBA8 bytes only has its last trace pass write them (no display
 * pass); the bytes must be those of the display pass (forced through the test seam
 * rs__gles_force_display_unfused) and those rs_image_quantize() makes of the same
 * renderer's float colour, byte for byte, over every method the last pass can be: traced
 * and rasterized primaries, one and several passes, shadow rays, maps and none, classic
 * environment maps (the whole frame one pass reading the maps at its end) and
 * inter-reflection, an odd frame size. Each case also proves which way ran from the
 * frame's kernel timings: a displayed frame has no "display" kernel, the forced one has
 * one; frames that need the float colour (rgb asked for, counters, the separate and paper
 * chains) keep the display pass. EGL (llvmpipe in CI); skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../backends/gles/gles_seams.h"
#include "test_gl_common.h"

#define MAX_W 64u
#define MAX_H 64u
#define MAX_PX (MAX_W * MAX_H)

/* The three images of one frame: displayed (the last pass writes RGBA8), the display pass
 * forced, and rs_image_quantize() of the float colour; with each frame's stats. */
struct frames {
	uint8_t fused[MAX_PX * 4], unfused[MAX_PX * 4], quantized[MAX_PX * 3];
	float rgb[MAX_PX * 3], depth_fused[MAX_PX], depth_unfused[MAX_PX];
	struct rs_render_stats s_fused, s_unfused, s_rgb;
};

static uint32_t calls(const struct rs_render_stats *s, const char *name)
{
	const struct rs_render_kernel_time *t = gl_kernel(s, name);
	return t ? t->calls : 0;
}

static void render(struct rs_renderer *r, const struct rs_frame *f, struct rs_render_stats *out)
{
	struct rs_error err = {0};
	if (rs_renderer_render(r, NULL, f, &err) != RS_OK)
		fail_msg("render: %s", err.message);
	*out = *rs_renderer_stats(r);
}

/* One renderer, one scene: the displayed frame first, then the forced display pass, then the
 * float colour (each frame starts from nothing: none can lean on the one before). */
static bool three_frames(const struct rs_render_desc *desc, const struct rs_scene *scene,
                         struct frames *f)
{
	struct rs_renderer *r = gl_open("egl", desc);
	if (!r)
		return false;
	struct rs_error err = {0};
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("set_scene: %s", err.message);
	rs__gles_force_display_unfused(false);
	render(r, &(struct rs_frame){.rgba8 = f->fused, .depth = f->depth_fused}, &f->s_fused);
	rs__gles_force_display_unfused(true);
	render(r, &(struct rs_frame){.rgba8 = f->unfused, .depth = f->depth_unfused},
	       &f->s_unfused);
	rs__gles_force_display_unfused(false);
	render(r, &(struct rs_frame){.rgb = f->rgb}, &f->s_rgb);
	rs_image_quantize(f->rgb, desc->width, desc->height, f->quantized);
	rs_renderer_destroy(&r);
	return true;
}

/* A channel's float colour c at a tie, c * 255 = k + 1/2 in fp32 (the environment's 0.3
 * is one: 76.5): display.glsl's floor(x + 0.5) and rs_image_quantize_value() both round it
 * up (the CPU's lrintf rounded it to even, one below, before 2026-12-03). Counted to show
 * the frames hold some. */
static bool tie(float c)
{
	float x = c * 255.0f;
	return c > 0.0f && c < 1.0f && x - floorf(x) == 0.5f;
}

/* The bytes of both ways agree, they are rs_image_quantize()'s of the float colour, ties
 * (above) included, and something is lit. */
static void same_bytes(const char *what, const struct rs_render_desc *desc, const struct frames *f)
{
	size_t n = (size_t)desc->width * desc->height, lit = 0, differ = 0, off = 0, ties = 0;
	for (size_t i = 0; i < n; ++i) {
		for (int c = 0; c < 3; ++c) {
			int a = f->fused[4 * i + c], q = f->quantized[3 * i + c];
			differ += a != f->unfused[4 * i + c];
			ties += tie(f->rgb[3 * i + c]);
			off += a != q;
			lit += a > 8;
		}
		assert_int_equal(f->fused[4 * i + 3], 255);
	}
	print_message("%s: %zu of %zu channels differ between the ways, %zu from the float "
	              "colour's (%zu ties among them), %zu lit\n",
	              what, differ, 3 * n, off, ties, lit);
	assert_int_equal(differ, 0);
	assert_int_equal(off, 0);
	assert_memory_equal(f->fused, f->unfused, n * 4);
	assert_memory_equal(f->depth_fused, f->depth_unfused, n * sizeof(float));
	assert_true(lit > n / 4);
}

/* desc on `scene`: the same bytes both ways, and the displayed frame ran no display pass and
 * as many trace passes as the forced one. */
static void displayed_as_the_display_pass(const char *what, struct rs_render_desc desc,
                                          const char *scene_name)
{
	struct rs_scene *scene = gl_scene(scene_name);
	static struct frames f;
	memset(&f, 0, sizeof f);
	if (!three_frames(&desc, scene, &f)) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	print_message("%s: trace %u / %u calls, display %u / %u\n", what,
	              calls(&f.s_fused, "trace"), calls(&f.s_unfused, "trace"),
	              calls(&f.s_fused, "display"), calls(&f.s_unfused, "display"));
	assert_true(calls(&f.s_fused, "trace") >= 1);
	assert_int_equal(calls(&f.s_fused, "trace"), calls(&f.s_unfused, "trace"));
	assert_int_equal(calls(&f.s_fused, "display"), 0);
	assert_int_equal(calls(&f.s_unfused, "display"), 1);
	/* a float frame needs the float colour: no displayed run, no display pass either */
	assert_int_equal(calls(&f.s_rgb, "display"), 0);
	same_bytes(what, &desc, &f);
	rs_scene_destroy(&scene);
}

static struct rs_render_desc base(uint32_t passes)
{
	return (struct rs_render_desc){
	    .width = MAX_W, .height = MAX_H, .passes = passes, .lights = 2};
}

static void tracer_box_two_passes(void **state)
{
	(void)state;
	displayed_as_the_display_pass("box, 2 passes", base(2), "box");
}

static void tracer_cow1_one_pass(void **state)
{
	(void)state;
	displayed_as_the_display_pass("cow1, 1 pass", base(1), "cow1");
}

static void tracer_mirrors_five_passes(void **state)
{
	(void)state;
	displayed_as_the_display_pass("mirrors, 5 passes", base(5), "mirrors");
}

static void shadow_maps_and_none(void **state)
{
	(void)state;
	struct rs_render_desc d = base(2);
	d.shadows = RS_SHADOW_MAP;
	d.shadow_map_size = 128;
	d.shadow_filter = 3;
	displayed_as_the_display_pass("cow1, shadow maps", d, "cow1");
	d = base(2);
	d.shadows = RS_SHADOW_NONE;
	displayed_as_the_display_pass("cow1, no shadows", d, "cow1");
}

/* Classic environment maps: a frame of 2 passes is one trace pass reading the maps for the
 * rays it leaves (rs_gles_step.mapped), and 1 pass reads none. */
static void classic_environment_map(void **state)
{
	(void)state;
	struct rs_render_desc d = base(2);
	d.reflections = RS_REFLECT_ENVMAP;
	d.envmap_size = 32;
	displayed_as_the_display_pass("mirrors, classic map, 2 passes", d, "mirrors");
	d.passes = 1;
	displayed_as_the_display_pass("mirrors, classic map, 1 pass", d, "mirrors");
	d = base(2);
	d.reflections = RS_REFLECT_ENVMAP;
	d.envmap_size = 32;
	d.shadows = RS_SHADOW_NONE;
	displayed_as_the_display_pass("mirrors, classic map, no shadows", d, "mirrors");
}

/* Inter-reflection: the maps are captured each frame by capture plans, which never display. */
static void inter_reflection(void **state)
{
	(void)state;
	struct rs_render_desc d = base(3);
	d.reflections = RS_REFLECT_INTERREFLECT;
	d.reflection_bounces = 2;
	d.envmap_size = 24;
	displayed_as_the_display_pass("mirrors, inter-reflection", d, "mirrors");
}

/* Rasterized primaries: the last pass is the first one over the visibility pass's hits
 * (1 pass) or a later one. */
static void raster_primaries(void **state)
{
	(void)state;
	struct rs_render_desc d = base(1);
	d.primary = RS_PRIMARY_RASTER;
	displayed_as_the_display_pass("cow1, raster, 1 pass", d, "cow1");
	d.passes = 3;
	displayed_as_the_display_pass("cow1, raster, 3 passes", d, "cow1");
}

/* An odd frame size (the per-pixel targets and the display target share the viewport). */
static void odd_frame_size(void **state)
{
	(void)state;
	struct rs_render_desc d = base(2);
	d.width = 37;
	d.height = 23;
	displayed_as_the_display_pass("box, 37x23", d, "box");
	d.reflections = RS_REFLECT_ENVMAP;
	d.envmap_size = 40; /* the targets larger than the frame */
	displayed_as_the_display_pass("mirrors, 37x23, classic map", d, "mirrors");
}

/* Where the float colour is needed, or the plan cannot, the display pass runs: both at once
 * (rgb and rgba8), counters (not the fused chain), the separate and paper chains. */
static void the_display_pass_stays_where_it_must(void **state)
{
	(void)state;
	struct rs_scene *scene = gl_scene("box");
	static uint8_t bytes[MAX_PX * 4], first[MAX_PX * 4];
	static float rgb[MAX_PX * 3];
	struct rs_render_desc descs[4] = {base(2), base(2), base(2), base(2)};
	descs[1].counters = true;
	descs[2].chain = RS_CHAIN_SEPARATE;
	descs[3].chain = RS_CHAIN_PAPER;
	rs__gles_force_display_unfused(false);
	for (int k = 0; k < 4; ++k) {
		struct rs_renderer *r = gl_open("egl", &descs[k]);
		if (!r) {
			rs_scene_destroy(&scene);
			gl_skip();
		}
		assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
		struct rs_render_stats s;
		/* rgb and rgba8 at once: the display pass, whatever the chain */
		render(r, &(struct rs_frame){.rgb = rgb, .rgba8 = first}, &s);
		assert_int_equal(calls(&s, "display"), 1);
		/* rgba8 alone: displayed only on the fused chain without counters; the same bytes
		 */
		render(r, &(struct rs_frame){.rgba8 = bytes}, &s);
		assert_int_equal(calls(&s, "display"), k == 0 ? 0 : 1);
		assert_memory_equal(bytes, first, sizeof bytes);
		/* and a float frame after a displayed one has its colour again */
		static float again[MAX_PX * 3];
		render(r, &(struct rs_frame){.rgb = again}, &s);
		assert_memory_equal(again, rgb, sizeof again);
		rs_renderer_destroy(&r);
	}
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(tracer_box_two_passes),
	    cmocka_unit_test(tracer_cow1_one_pass),
	    cmocka_unit_test(tracer_mirrors_five_passes),
	    cmocka_unit_test(shadow_maps_and_none),
	    cmocka_unit_test(classic_environment_map),
	    cmocka_unit_test(inter_reflection),
	    cmocka_unit_test(raster_primaries),
	    cmocka_unit_test(odd_frame_size),
	    cmocka_unit_test(the_display_pass_stays_where_it_must),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
