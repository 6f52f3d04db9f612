/* Wide nodes (--nodes wide4, docs/bvh.md "Wide nodes") in the GL kernels: every pixel sees
 * the same triangle and the frame is bit for bit the compact nodes' one (R3: conservative
 * quantised boxes, R4: the closest hit does not depend on visiting order), on Cow1 and on
 * box fields far from the origin, at tiny and huge scales and flat in one plane; and the
 * kernels' hit numbers (child-box tests, triangle tests) equal the CPU reference's walking
 * the same wide layout within 0.02 %. EGL; skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"
#include "test_gl_field.h"

#define SIZE 48u

struct image {
	float rgb[SIZE * SIZE * 3], depth[SIZE * SIZE];
	uint32_t triangle[SIZE * SIZE];
	uint64_t boxes, triangles;
};

/* One frame of `scene` under desc with the node format, on `backend` ("cpu" included). */
static bool render(const char *backend, struct rs_render_desc desc, enum rs_pack_nodes nodes,
                   const struct rs_scene *scene, struct image *out)
{
	desc.pack.nodes = nodes;
	struct rs_renderer *r = NULL;
	struct rs_error err;
	if (!strcmp(backend, "cpu")) {
		if (rs_renderer_create_cpu(&desc, &r, &err) != RS_OK)
			fail_msg("cpu: %s", err.message);
	} else if (!(r = gl_open(backend, &desc)))
		return false;
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("%s set_scene: %s", backend, err.message);
	struct rs_frame frame = {.rgb = out->rgb, .depth = out->depth, .triangle = out->triangle};
	if (rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		fail_msg("%s render: %s", backend, err.message);
	out->boxes = rs_renderer_stats(r)->box_tests;
	out->triangles = rs_renderer_stats(r)->triangle_tests;
	rs_renderer_destroy(&r);
	return true;
}

static bool near_count(uint64_t gpu, uint64_t cpu)
{
	double d = (double)gpu - (double)cpu;
	return fabs(d) <= 2e-4 * (double)cpu;
}

static void same_as_compact(const char *what, struct rs_scene *scene)
{
	static struct image compact, wide, cpu;
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 2, .lights = 1};
	if (!render("egl", desc, RS_PACK_NODES_COMPACT, scene, &compact)) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	assert_true(render("egl", desc, RS_PACK_NODES_WIDE4, scene, &wide));
	size_t hits = 0;
	for (size_t i = 0; i < SIZE * SIZE; i++)
		hits += compact.triangle[i] != RS_NO_SLOT;
	print_message("%s: %zu of %u pixels hit\n", what, hits, SIZE * SIZE);
	assert_true(hits > SIZE * SIZE / 16);
	assert_memory_equal(compact.triangle, wide.triangle, sizeof wide.triangle);
	assert_memory_equal(compact.depth, wide.depth, sizeof wide.depth);
	assert_memory_equal(compact.rgb, wide.rgb, sizeof wide.rgb);
	/* the separate chain counts: the kernels' walk against the CPU's */
	desc.counters = true;
	assert_true(render("egl", desc, RS_PACK_NODES_WIDE4, scene, &wide));
	render("cpu", desc, RS_PACK_NODES_WIDE4, scene, &cpu);
	print_message("%s: boxes %llu gpu, %llu cpu; triangles %llu gpu, %llu cpu\n", what,
	              (unsigned long long)wide.boxes, (unsigned long long)cpu.boxes,
	              (unsigned long long)wide.triangles, (unsigned long long)cpu.triangles);
	assert_true(cpu.boxes > 0 && near_count(wide.boxes, cpu.boxes));
	assert_true(near_count(wide.triangles, cpu.triangles));
	rs_scene_destroy(&scene);
}

static void wide_nodes_render_the_compact_frames_of_cow1(void **state)
{
	same_as_compact("cow1", gl_scene("cow1"));
}

static void wide_nodes_render_the_compact_frames_far_tiny_huge_and_flat(void **state)
{
	const double zero[3] = {0, 0, 0}, far[3] = {1e6, -1e6, 1e6}, mid[3] = {123.5, 7, -40};
	same_as_compact("field", field(1.0, zero, false, SIZE));
	same_as_compact("field 1e-3", field(1e-3, zero, false, SIZE));
	same_as_compact("field 1e4", field(1e4, zero, false, SIZE));
	same_as_compact("field at 1e6", field(1.0, far, false, SIZE));
	same_as_compact("flat field", field(1.0, mid, true, SIZE));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(wide_nodes_render_the_compact_frames_of_cow1),
	    cmocka_unit_test(wide_nodes_render_the_compact_frames_far_tiny_huge_and_flat),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
