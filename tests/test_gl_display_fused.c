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
	gl_render_frame(r, &(struct rs_frame){.rgba8 = f->fused, .depth = f->depth_fused},
	                &f->s_fused);
	rs__gles_force_display_unfused(true);
	gl_render_frame(r, &(struct rs_frame){.rgba8 = f->unfused, .depth = f->depth_unfused},
	                &f->s_unfused);
	rs__gles_force_display_unfused(false);
	gl_render_frame(r, &(struct rs_frame){.rgb = f->rgb}, &f->s_rgb);
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
	              gl_calls(&f.s_fused, "trace"), gl_calls(&f.s_unfused, "trace"),
	              gl_calls(&f.s_fused, "display"), gl_calls(&f.s_unfused, "display"));
	assert_true(gl_calls(&f.s_fused, "trace") >= 1);
	assert_int_equal(gl_calls(&f.s_fused, "trace"), gl_calls(&f.s_unfused, "trace"));
	assert_int_equal(gl_calls(&f.s_fused, "display"), 0);
	assert_int_equal(gl_calls(&f.s_unfused, "display"), 1);
	/* a float frame needs the float colour: no displayed run, no display pass either */
	assert_int_equal(gl_calls(&f.s_rgb, "display"), 0);
	same_bytes(what, &desc, &f);
	rs_scene_destroy(&scene);
}

/* Every method the last pass can be (test_gl_common.h, gl_fused_cases). */
static void every_fused_method(void **state)
{
	(void)state;
	struct gl_fused_case cases[GL_FUSED_CASES];
	gl_fused_cases(MAX_W, MAX_H, cases);
	for (int i = 0; i < GL_FUSED_CASES; ++i)
		displayed_as_the_display_pass(cases[i].what, cases[i].desc, cases[i].scene);
}

/* Where the float colour is needed, or the plan cannot, the display pass runs: both at once
 * (rgb and rgba8), counters (not the fused chain), the separate and paper chains. */
static void the_display_pass_stays_where_it_must(void **state)
{
	(void)state;
	struct rs_scene *scene = gl_scene("box");
	static uint8_t bytes[MAX_PX * 4], first[MAX_PX * 4];
	static float rgb[MAX_PX * 3];
	struct rs_render_desc descs[4] = {
	    gl_fused_desc(MAX_W, MAX_H, 2), gl_fused_desc(MAX_W, MAX_H, 2),
	    gl_fused_desc(MAX_W, MAX_H, 2), gl_fused_desc(MAX_W, MAX_H, 2)};
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
		gl_render_frame(r, &(struct rs_frame){.rgb = rgb, .rgba8 = first}, &s);
		assert_int_equal(gl_calls(&s, "display"), 1);
		/* rgba8 alone: displayed only on the fused chain without counters; the same bytes
		 */
		gl_render_frame(r, &(struct rs_frame){.rgba8 = bytes}, &s);
		assert_int_equal(gl_calls(&s, "display"), k == 0 ? 0 : 1);
		assert_memory_equal(bytes, first, sizeof bytes);
		/* and a float frame after a displayed one has its colour again */
		static float again[MAX_PX * 3];
		gl_render_frame(r, &(struct rs_frame){.rgb = again}, &s);
		assert_memory_equal(again, rgb, sizeof again);
		rs_renderer_destroy(&r);
	}
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(every_fused_method),
	    cmocka_unit_test(the_display_pass_stays_where_it_must),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
