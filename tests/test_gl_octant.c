/* Octant node orders (--nodes compact:octant, paper:octant; docs/bvh.md "Node orders") in the
 * GL kernels: eight pre-orders of the tree, the ray's octant picking one, each visiting at
 * every node first the child nearer along the node's split axis for that octant's sign. The
 * frames (ids, depth, colour) are bit for bit the default directional orders' (R4: the
 * closest hit does not depend on the visiting order), on Cow1 and on instanced Cow17 in
 * two levels, on every chain and in the hits-only kernel; and the kernels' hit numbers equal
 * the CPU reference's walking the same eight orders as closely as the directional walk's
 * equal the CPU's (+ 2e-4; boxes within 5e-4 as test_gl_two_level), and differ from the
 * directional walk's (the order is really used).
 * EGL; skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"

#define SIZE 64u
#include "test_gl_same_frame.h"

/* The octant walk's GPU count as near the CPU's as the directional walk's is (the fp32 camera
 * rays differ from the double ones in a few pixels: a few tests either way at this size),
 * plus 2e-4 of the count. */
static bool as_near(uint64_t gpu, uint64_t cpu, uint64_t gpu_dir, uint64_t cpu_dir)
{
	double d = fabs((double)gpu - (double)cpu), d_dir = fabs((double)gpu_dir - (double)cpu_dir);
	return d <= d_dir + 2e-4 * (double)cpu;
}

/* The hits-only kernel's primary ids and distances (primary.glsl; no colour). */
static void hits_only(struct rs_render_desc desc, const struct rs_scene *scene, uint32_t *ids,
                      float *depth)
{
	desc.hits_only = true;
	struct rs_renderer *r = gl_open("egl", &desc);
	struct rs_error err;
	assert_non_null(r);
	struct rs_frame frame = {.depth = depth, .triangle = ids};
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK ||
	    rs_renderer_render(r, NULL, &frame, &err) != RS_OK)
		fail_msg("hits_only: %s", err.message);
	rs_renderer_destroy(&r);
}

/* `scene` under desc with directional and with octant orders of `nodes`: the same frames
 * on egl, and the GPU's counts (separate chain) the CPU's for octant orders. */
static void octant_as_directional(const char *what, struct rs_scene *scene,
                                  enum rs_pack_nodes nodes, bool two_level)
{
	static struct image dir, oct, cpu_dir, cpu_oct, gpu;
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 2, .lights = 1};
	desc.pack.nodes = nodes;
	desc.instances = two_level ? RS_INSTANCES_TWO_LEVEL : RS_INSTANCES_AUTO;
	if (!render("egl", desc, scene, &dir)) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	desc.pack.orders = RS_PACK_ORDERS_OCTANT;
	assert_true(render("egl", desc, scene, &oct));
	assert_true(same_frame(what, &oct, &dir) > SIZE * SIZE / 8);
	assert_memory_equal(oct.triangle, dir.triangle, sizeof dir.triangle);
	assert_memory_equal(oct.depth, dir.depth, sizeof dir.depth);
	assert_memory_equal(oct.rgb, dir.rgb, sizeof dir.rgb);
	/* the hits-only kernel (primary.glsl): the same ids and distances in both orders */
	hits_only(desc, scene, oct.triangle, oct.depth);
	desc.pack.orders = RS_PACK_ORDERS_DIRECTIONAL;
	hits_only(desc, scene, gpu.triangle, gpu.depth);
	desc.pack.orders = RS_PACK_ORDERS_OCTANT;
	assert_memory_equal(oct.triangle, dir.triangle, sizeof dir.triangle);
	assert_memory_equal(oct.triangle, gpu.triangle, sizeof gpu.triangle);
	assert_memory_equal(oct.depth, gpu.depth, sizeof gpu.depth);
	/* the separate chain counts: the kernels' walk against the CPU's, both octant */
	desc.counters = true;
	desc.chain = RS_CHAIN_SEPARATE;
	assert_true(render("egl", desc, scene, &gpu));
	render("cpu", desc, scene, &cpu_oct);
	desc.pack.orders = RS_PACK_ORDERS_DIRECTIONAL;
	render("cpu", desc, scene, &cpu_dir);
	static struct image gpu_dir;
	assert_true(render("egl", desc, scene, &gpu_dir));
	print_message("%s: octant boxes %llu gpu, %llu cpu, triangles %llu gpu, %llu cpu; "
	              "directional boxes %llu gpu, %llu cpu, triangles %llu gpu, %llu cpu\n",
	              what, (unsigned long long)gpu.boxes, (unsigned long long)cpu_oct.boxes,
	              (unsigned long long)gpu.triangles, (unsigned long long)cpu_oct.triangles,
	              (unsigned long long)gpu_dir.boxes, (unsigned long long)cpu_dir.boxes,
	              (unsigned long long)gpu_dir.triangles, (unsigned long long)cpu_dir.triangles);
	assert_true(cpu_oct.boxes > 0 && cpu_oct.boxes != cpu_dir.boxes);
	assert_memory_equal(cpu_oct.triangle, cpu_dir.triangle, sizeof cpu_dir.triangle);
	assert_true(near_count(gpu.boxes, cpu_oct.boxes));
	assert_true(as_near(gpu.boxes, cpu_oct.boxes, gpu_dir.boxes, cpu_dir.boxes));
	assert_true(
	    as_near(gpu.triangles, cpu_oct.triangles, gpu_dir.triangles, cpu_dir.triangles));
	rs_scene_destroy(&scene);
}

static void octant_orders_render_the_directional_frames_of_cow1(void **state)
{
	octant_as_directional("cow1 compact", gl_scene("cow1"), RS_PACK_NODES_COMPACT, false);
	octant_as_directional("cow1 paper", gl_scene("cow1"), RS_PACK_NODES_PAPER, false);
}

static void octant_orders_render_the_directional_frames_of_cow17i_in_two_levels(void **state)
{
	octant_as_directional("cow17i two-level", gl_scene("cow17i"), RS_PACK_NODES_COMPACT, true);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(octant_orders_render_the_directional_frames_of_cow1),
	    cmocka_unit_test(octant_orders_render_the_directional_frames_of_cow17i_in_two_levels),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
