/* CowNi: the Cow scenes as instances of one cow. Same triangles as the flattened CowN; the
 * two-level packing of Cow17i takes at most a tenth of the flattened packing's bytes, and its
 * two-level walk hits the same triangle as the flattened scene's walk on >= 99.99 % of the
 * camera's rays. Frame N of CowNi is frame N of CowN (moved by instance transforms). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_pack.h"
#include "raystream/rs_render.h"
#include "raystream/rs_scenegen.h"
#include "raystream/rs_trace.h"

static struct rs_scene *build(const char *name)
{
	struct rs_scenegen_desc desc;
	struct rs_scene *scene = NULL;
	struct rs_error err = {0};
	assert_int_equal(rs_scenegen_parse(name, &desc, &err), RS_OK);
	if (rs_scenegen_build(&desc, &scene, &err) != RS_OK) {
		printf("%s\n", err.message);
		fail();
	}
	return scene;
}

static void names_parse_and_print(void **state)
{
	struct rs_scenegen_desc desc;
	char name[32];
	assert_int_equal(rs_scenegen_parse("cow17i", &desc, NULL), RS_OK);
	assert_true(desc.instanced && desc.cows == 17);
	assert_int_equal(rs_scenegen_name(&desc, name, sizeof name, NULL), RS_OK);
	assert_string_equal(name, "cow17i");
	assert_int_equal(rs_scenegen_parse("cow17", &desc, NULL), RS_OK);
	assert_false(desc.instanced);
	assert_int_equal(rs_scenegen_parse("cowi", &desc, NULL), RS_ERR_INVALID);
	assert_int_equal(rs_scenegen_parse("cow17ii", &desc, NULL), RS_ERR_INVALID);
	assert_int_equal(rs_scenegen_parse("cow1i7", &desc, NULL), RS_ERR_INVALID);
}

static void pack_flat(const struct rs_scene *scene, struct rs_packed *out)
{
	size_t tris = rs_scene_triangle_count(scene);
	struct rs_bvh_desc bvh = {0};
	size_t cap = rs_bvh_node_bound(&bvh, tris), count = 0;
	struct rs_bvh_node *nodes = malloc(cap * sizeof *nodes);
	uint32_t *order = malloc(tris * sizeof *order);
	assert_non_null(nodes);
	assert_non_null(order);
	assert_int_equal(rs_bvh_build(&bvh, rs_scene_positions(scene), rs_scene_vertex_count(scene),
	                              rs_scene_indices(scene), tris, nodes, cap, order, &count,
	                              NULL),
	                 RS_OK);
	assert_int_equal(
	    rs_pack_layout(NULL, count, tris, rs_scene_material_count(scene), out, NULL), RS_OK);
	assert_int_equal(rs_pack_alloc(out, NULL), RS_OK);
	assert_int_equal(rs_pack_scene(scene, nodes, count, order, out, NULL), RS_OK);
	free(nodes);
	free(order);
}

static void cow17i_is_cow17_in_a_tenth_of_the_bytes(void **state)
{
	struct rs_scene *flat = build("cow17"), *inst = build("cow17i");
	size_t tris = rs_scene_triangle_count(flat);
	assert_int_equal(rs_scene_triangle_count(inst), tris);
	assert_int_equal(rs_scene_instance_count(inst), 17);
	assert_int_equal(rs_scene_prototype_count(inst), 1);
	/* the same vertices, to rounding of the placement arithmetic */
	const double *a = rs_scene_positions_f64(flat), *b = rs_scene_positions_f64(inst);
	assert_int_equal(rs_scene_vertex_count(inst), rs_scene_vertex_count(flat));
	for (size_t v = 0; v < rs_scene_vertex_count(flat) * 3; v++)
		assert_true(fabs(a[v] - b[v]) <= 1e-12 * (1.0 + fabs(a[v])));
	assert_memory_equal(rs_scene_indices(flat), rs_scene_indices(inst),
	                    tris * 3 * sizeof(uint32_t));
	assert_memory_equal(rs_scene_triangle_materials(flat), rs_scene_triangle_materials(inst),
	                    tris * sizeof(uint32_t));

	struct rs_packed one;
	struct rs_packed_instances two;
	pack_flat(flat, &one);
	assert_int_equal(rs_pack_instances(inst, NULL, NULL, &two, NULL), RS_OK);
	size_t flat_bytes = rs_pack_bytes(&one), two_bytes = rs_pack_instances_bytes(&two);
	printf("cow17 packed: flattened %zu bytes, two-level %zu bytes (%.3f)\n", flat_bytes,
	       two_bytes, (double)two_bytes / (double)flat_bytes);
	assert_true(two_bytes * 10 <= flat_bytes);

	/* the camera's view: rays from its eye through a grid over the scene's bounds */
	const struct rs_camera *cam = rs_scene_camera(flat);
	struct rs_bounds bounds;
	rs_scene_bounds(flat, &bounds);
	const uint32_t grid = 100;
	uint32_t same = 0, hits = 0;
	struct rs_trace_counters c1 = {0}, c2 = {0};
	for (uint32_t y = 0; y < grid; y++)
		for (uint32_t x = 0; x < grid; x++) {
			double target[3] = {
			    bounds.lo[0] + (bounds.hi[0] - bounds.lo[0]) * (x + 0.5) / grid,
			    bounds.lo[1] + (bounds.hi[1] - bounds.lo[1]) * (y + 0.5) / grid,
			    0.5 * (bounds.lo[2] + bounds.hi[2])};
			struct rs_ray ray = {.tmax = INFINITY, .skip_slot = RS_NO_SLOT};
			for (int k = 0; k < 3; k++) {
				ray.origin[k] = cam->eye[k];
				ray.dir[k] = target[k] - cam->eye[k];
			}
			struct rs_hit h1;
			struct rs_instance_hit h2;
			bool f1 = rs_trace_closest(&one, RS_TRIANGLE_WATERTIGHT, &ray, &h1, &c1);
			bool f2 = rs_trace_instances_closest(&two, RS_TRIANGLE_WATERTIGHT, &ray,
			                                     &h2, &c2);
			hits += f1;
			same += f1 == f2 && (!f1 || h1.triangle == h2.hit.triangle);
		}
	printf("cow17 %u rays: %u hits, %u the same triangle; box/triangle tests flattened "
	       "%llu/%llu, two-level %llu/%llu\n",
	       grid * grid, hits, same, (unsigned long long)c1.box_tests,
	       (unsigned long long)c1.triangle_tests, (unsigned long long)c2.box_tests,
	       (unsigned long long)c2.triangle_tests);
	assert_true(hits > grid * grid / 2);
	assert_true((double)same >= 0.9999 * grid * grid);
	rs_pack_instances_free(&two);
	rs_pack_free(&one);
	rs_scene_destroy(&flat);
	rs_scene_destroy(&inst);
}

static struct rs_scene *frame(const char *name, uint32_t f)
{
	struct rs_scene *scene = NULL;
	struct rs_error err = {0};
	if (rs_scenegen_load_frame(name, f, 30, &scene, &err) != RS_OK) {
		printf("%s frame %u: %s\n", name, f, err.message);
		fail();
	}
	return scene;
}

#define VIEW 100u

static void render_ids(struct rs_renderer *r, uint32_t *ids)
{
	struct rs_frame f = {.triangle = ids};
	struct rs_error err;
	if (rs_renderer_render(r, NULL, &f, &err) != RS_OK)
		fail_msg("render: %s", err.message);
}

/* Frame N of cow5i is frame N of cow5: the swaying cow (N / 2) has CowN's sway as its
 * transform, the stage does not move by a bit, and a CPU renderer moved there by
 * rs_renderer_update_instances hits the triangle a set_scene of cow5 frame N hits on
 * >= 99.99 % of pixels. */
static void cow5i_frame_n_is_cow5_frame_n(void **state)
{
	(void)state;
	struct rs_scene *rest = frame("cow5i", 0);
	const struct rs_render_desc d = {.width = VIEW, .height = VIEW, .threads = 2, .passes = 1};
	struct rs_renderer *moved = NULL, *flat = NULL;
	assert_int_equal(rs_renderer_create_cpu(&d, &moved, NULL), RS_OK);
	assert_int_equal(rs_renderer_create_cpu(&d, &flat, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(moved, rest, NULL), RS_OK);
	uint32_t *a = malloc(VIEW * VIEW * sizeof *a), *b = malloc(VIEW * VIEW * sizeof *b);
	assert_non_null(a);
	assert_non_null(b);
	struct rs_scene *inst[3] = {0}, *cows[3] = {0};
	const uint32_t frames[3] = {1, 20, 45};
	for (int k = 0; k < 3; k++) {
		inst[k] = frame("cow5i", frames[k]);
		cows[k] = frame("cow5", frames[k]);
		size_t nv = rs_scene_vertex_count(cows[k]), tris = rs_scene_triangle_count(cows[k]);
		assert_int_equal(rs_scene_vertex_count(inst[k]), nv);
		const double *p = rs_scene_positions_f64(cows[k]),
		             *q = rs_scene_positions_f64(inst[k]);
		for (size_t v = 0; v < nv * 3; v++)
			assert_true(fabs(p[v] - q[v]) <= 1e-12 * (1.0 + fabs(p[v])));
		assert_memory_equal(rs_scene_indices(cows[k]), rs_scene_indices(inst[k]),
		                    tris * 3 * sizeof(uint32_t));
		/* only cow 2 moved; the stage (after the herd) is frame 0's to the bit */
		const struct rs_scene_instance *i0 = rs_scene_instances(rest),
		                               *ik = rs_scene_instances(inst[k]);
		for (int c = 0; c < 5; c++)
			assert_true((memcmp(i0[c].transform, ik[c].transform,
			                    sizeof i0[c].transform) != 0) == (c == 2));
		size_t herd_v = rs_scene_indices(
		    rest)[(size_t)(i0[4].first_triangle + i0[4].triangle_count) * 3];
		assert_memory_equal(rs_scene_positions_f64(rest) + herd_v * 3, q + herd_v * 3,
		                    (nv - herd_v) * 3 * sizeof(double));
		struct rs_error err;
		if (rs_renderer_update_instances(moved, inst[k], &err) != RS_OK)
			fail_msg("update to frame %u: %s", frames[k], err.message);
		assert_int_equal(rs_renderer_set_scene(flat, cows[k], NULL), RS_OK);
		render_ids(moved, a);
		render_ids(flat, b);
		uint32_t same = 0, hits = 0;
		for (uint32_t px = 0; px < VIEW * VIEW; px++) {
			same += a[px] == b[px];
			hits += b[px] != RS_NO_SLOT;
		}
		printf("cow5i frame %u: %u of %u pixels hit cow5's triangle (%u hits)\n", frames[k],
		       same, VIEW * VIEW, hits);
		assert_true(hits > VIEW * VIEW / 4);
		assert_true((double)same >= 0.9999 * VIEW * VIEW);
	}
	assert_int_equal(rs_renderer_stats(moved)->instance_updates, 3);
	rs_renderer_destroy(&moved);
	rs_renderer_destroy(&flat);
	for (int k = 0; k < 3; k++) {
		rs_scene_destroy(&inst[k]);
		rs_scene_destroy(&cows[k]);
	}
	rs_scene_destroy(&rest);
	free(a);
	free(b);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(names_parse_and_print),
	    cmocka_unit_test(cow17i_is_cow17_in_a_tenth_of_the_bytes),
	    cmocka_unit_test(cow5i_frame_n_is_cow5_frame_n),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
