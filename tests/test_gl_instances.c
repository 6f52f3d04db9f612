/* Instanced scenes through the renderers: Cow17i (seventeen instances of one cow) renders as
 * the flattened Cow17 on the CPU reference and on EGL (same triangle on >= 99.99 % of pixels,
 * >= 60 dB); hit numbers on Cow17i equal Cow17's on each backend, and the kernels' equal the
 * CPU's within 0.05 % (fp32 against double near box faces; flattened Cow17 differs as much). This
 * pins `instances = flatten` (the baked world-space triangles, docs/bvh.md "Instances") to the
 * flattened scene's frames; test_gl_two_level covers the two-level walk. EGL; skipped without a
 * context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"
#include "test_trace_render_fixture.h"

#define SIZE 64u
#include "test_gl_same_frame.h"

static void cow17i_renders_as_cow17_on_cpu_and_egl(void **state)
{
	static struct image flat_cpu, inst_cpu, flat_gl, inst_gl;
	struct rs_scene *flat = gl_scene("cow17"), *inst = gl_scene("cow17i");
	assert_int_equal(rs_scene_instance_count(inst), 17);
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 1,
	                              .counters = true,
	                              .instances = RS_INSTANCES_FLATTEN};
	render("cpu", desc, flat, &flat_cpu);
	render("cpu", desc, inst, &inst_cpu);
	assert_true(same_frame("cpu cow17i vs cow17", &inst_cpu, &flat_cpu) > SIZE * SIZE / 4);
	if (!render("egl", desc, flat, &flat_gl)) {
		rs_scene_destroy(&flat);
		rs_scene_destroy(&inst);
		gl_skip();
	}
	assert_true(render("egl", desc, inst, &inst_gl));
	assert_true(same_frame("egl cow17i vs cow17", &inst_gl, &flat_gl) > SIZE * SIZE / 4);
	assert_true(same_frame("egl cow17i vs cpu cow17", &inst_gl, &flat_cpu) > SIZE * SIZE / 4);
	print_message("cow17i: boxes %llu gpu, %llu cpu; triangles %llu gpu, %llu cpu\n",
	              (unsigned long long)inst_gl.boxes, (unsigned long long)inst_cpu.boxes,
	              (unsigned long long)inst_gl.triangles,
	              (unsigned long long)inst_cpu.triangles);
	print_message("cow17: boxes %llu gpu, %llu cpu; triangles %llu gpu, %llu cpu\n",
	              (unsigned long long)flat_gl.boxes, (unsigned long long)flat_cpu.boxes,
	              (unsigned long long)flat_gl.triangles,
	              (unsigned long long)flat_cpu.triangles);
	assert_true(inst_cpu.boxes > 0);
	/* instanced = flattened on each backend, exactly */
	assert_true(inst_gl.boxes == flat_gl.boxes && inst_gl.triangles == flat_gl.triangles);
	assert_true(inst_cpu.boxes == flat_cpu.boxes && inst_cpu.triangles == flat_cpu.triangles);
	/* GPU against CPU: flattened Cow17 at this size already differs by 4 triangle tests of
	 * 14,261 (fp32 near box faces), so the same bound for both */
	assert_true(near_count(inst_gl.boxes, inst_cpu.boxes));
	assert_true(near_count(inst_gl.triangles, inst_cpu.triangles));
	rs_scene_destroy(&flat);
	rs_scene_destroy(&inst);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(cow17i_renders_as_cow17_on_cpu_and_egl),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
