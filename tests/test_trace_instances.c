/* The two-level walk (rs_pack_instances + rs_trace_instances_closest) against the same
 * instances baked into world space and walked in one level: same triangle hit on >= 99.99 %
 * of rays, the same t and a geometric normal on the same side, for rotated, scaled,
 * non-uniformly scaled, mirrored and far-from-origin instances, with plain meshes between; a closed
 * room of instanced walls leaks no ray and shadows no interior point; wide4 and instance-less
 * scenes are refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_pack.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_trace.h"

#include "test_instances_shapes.h"

/* The baked triangles walked in one level, as every renderer does today. */
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

/* World geometric normal of baked triangle `id`: e1 x e2 of its (wound) world vertices. */
static void baked_normal(const struct rs_scene *scene, uint32_t id, double n[3])
{
	const uint32_t *t = rs_scene_indices(scene) + id * 3;
	const double *p = rs_scene_positions_f64(scene);
	double e1[3], e2[3];
	for (int a = 0; a < 3; a++) {
		e1[a] = p[t[1] * 3 + a] - p[t[0] * 3 + a];
		e2[a] = p[t[2] * 3 + a] - p[t[0] * 3 + a];
	}
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

/* Rays from `eye` through a grid spanning the scene's bounds: the two walks agree. */
static void compare_walks(struct rs_scene *scene, const double eye[3], uint32_t grid)
{
	struct rs_packed flat;
	struct rs_packed_instances two;
	pack_flat(scene, &flat);
	assert_int_equal(rs_pack_instances(scene, NULL, NULL, &two, NULL), RS_OK);
	struct rs_packed_two_level merged;
	assert_int_equal(rs_pack_two_level(scene, &two, &merged, NULL), RS_OK);
	struct rs_bounds b;
	rs_scene_bounds(scene, &b);
	uint32_t same = 0, rays = 0, hits = 0, same_merged = 0;
	struct rs_trace_counters c1 = {0}, c2 = {0};
	for (uint32_t y = 0; y < grid; y++)
		for (uint32_t x = 0; x < grid; x++) {
			double target[3] = {b.lo[0] + (b.hi[0] - b.lo[0]) * (x + 0.5) / grid,
			                    b.lo[1] + (b.hi[1] - b.lo[1]) * (y + 0.5) / grid,
			                    0.5 * (b.lo[2] + b.hi[2])};
			struct rs_ray ray = {
			    .tmin = 0.0, .tmax = INFINITY, .skip_slot = RS_NO_SLOT};
			for (int a = 0; a < 3; a++) {
				ray.origin[a] = eye[a];
				ray.dir[a] = target[a] - eye[a];
			}
			struct rs_hit h1;
			struct rs_instance_hit h2;
			bool f1 = rs_trace_closest(&flat, RS_TRIANGLE_WATERTIGHT, &ray, &h1, &c1);
			bool f2 = rs_trace_instances_closest(&two, RS_TRIANGLE_WATERTIGHT, &ray,
			                                     &h2, &c2);
			/* the merged layout the kernels read, rays in its frame */
			struct rs_ray local = ray;
			for (int a = 0; a < 3; a++)
				local.origin[a] -= merged.all.origin[a];
			struct rs_instance_hit h4;
			bool f4 = rs_trace_two_level_closest(&merged, RS_TRIANGLE_WATERTIGHT,
			                                     &local, &h4, NULL);
			same_merged += f1 == f4 && (!f1 || h1.triangle == h4.hit.triangle);
			if (f4) {
				assert_true(fabs(h2.hit.t - h4.hit.t) <= 1e-5 * h2.hit.t);
				local.tmax = h4.hit.t * 1.0001;
				assert_true(rs_trace_two_level_occluded(
				    &merged, RS_TRIANGLE_WATERTIGHT, &local, NULL));
				local.skip_slot = h4.hit.triangle;
				for (int a = 0; a < 3; a++)
					local.origin[a] += 0.999 * h4.hit.t * ray.dir[a];
				local.tmax = INFINITY;
				struct rs_instance_hit h5;
				rs_trace_two_level_closest(&merged, RS_TRIANGLE_WATERTIGHT, &local,
				                           &h5, NULL);
				assert_true(h5.hit.triangle != h4.hit.triangle);
			}
			rays++;
			hits += f1;
			if (f1 != f2 || (f1 && h1.triangle != h2.hit.triangle))
				continue;
			same++;
			if (!f1)
				continue;
			assert_true(fabs(h1.t - h2.hit.t) <= 1e-5 * h1.t);
			double n[3];
			baked_normal(scene, h1.triangle, n);
			double d = n[0] * h2.normal[0] + n[1] * h2.normal[1] + n[2] * h2.normal[2];
			assert_true(d > 0.0);
			/* skip_slot is a scene triangle id here: a ray from just before the hit
			 * that skips it never reports it */
			struct rs_ray from = ray;
			for (int a = 0; a < 3; a++)
				from.origin[a] = ray.origin[a] + 0.999 * h1.t * ray.dir[a];
			from.skip_slot = h2.hit.triangle;
			struct rs_instance_hit h3;
			rs_trace_instances_closest(&two, RS_TRIANGLE_WATERTIGHT, &from, &h3, NULL);
			assert_true(h3.hit.triangle != h2.hit.triangle);
			/* occlusion agrees with the closest hit */
			ray.tmax = h1.t * 1.0001;
			assert_true(
			    rs_trace_instances_occluded(&two, RS_TRIANGLE_WATERTIGHT, &ray, NULL));
		}
	assert_true(hits > rays / 4); /* the grid does see the instances */
	assert_true((double)same >= 0.9999 * rays);
	print_message("%u rays, %u hits: %u the same triangle two-level, %u merged\n", rays, hits,
	              same, same_merged);
	assert_true((double)same_merged >= 0.9999 * rays);
	assert_true(c2.triangle_tests > 0 && c2.box_tests > 0);
	rs_pack_two_level_free(&merged);
	rs_pack_instances_free(&two);
	rs_pack_free(&flat);
}

static void transformed_instances_hit_as_baked(void **state)
{
	struct rs_scene *scene = new_scene();
	uint32_t sphere = add_sphere(scene);
	const double x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, tilt[3] = {1, 2, 3};
	struct {
		const double *axis;
		double angle, scale[3], move[3];
	} set[] = {
	    {x, 0.0, {1, 1, 1}, {0, 0, 0}},
	    {y, 0.8, {1, 1, 1}, {2.5, 0, 0}},
	    {tilt, 1.3, {1.5, 1.5, 1.5}, {-3, 0.5, 0}},
	    {x, 0.4, {2.0, 0.5, 1.0}, {0, 2.5, 0.5}},
	    {y, 0.0, {-1, 1, 1}, {0, -2.5, 0}},
	    {tilt, 2.0, {1.2, -0.7, 0.9}, {3, 2.5, -1}},
	    {x, 0.0, {0.5, 0.5, 0.5}, {0.7, 0.4, 1.3}}, /* overlaps the first: ties and order */
	};
	struct rs_material red = {.diffuse = {1, 0, 0}};
	assert_int_equal(rs_scene_add_material(scene, &red, NULL, NULL), RS_OK);
	add_floor(scene, -3.5, 0); /* plain meshes around the instances: the loose BLAS */
	for (size_t i = 0; i < sizeof set / sizeof set[0]; i++) {
		if (i == 3)
			add_floor(scene, -3.0, 1);
		struct rs_instance_desc d = {.mesh = sphere};
		make_transform(set[i].axis, set[i].angle, set[i].scale, set[i].move, d.transform);
		assert_int_equal(rs_scene_add_instance(scene, &d, NULL, NULL), RS_OK);
	}
	add_floor(scene, -2.5, 1);
	const double eye[3] = {0.3, 6.0, 12.0};
	compare_walks(scene, eye, 150);
	rs_scene_destroy(&scene);
}

static void far_from_origin_instances_hit_as_baked(void **state)
{
	struct rs_scene *scene = new_scene();
	uint32_t sphere = add_sphere(scene);
	const double far[3] = {1e6, -2e6, 3e6}, tilt[3] = {3, 1, 2};
	for (int i = 0; i < 9; i++) {
		const double scale[3] = {1.0, 1.0 + 0.1 * i, i % 2 ? -1.0 : 1.0};
		const double move[3] = {far[0] + 2.5 * (i % 3), far[1] + 2.5 * (i / 3), far[2]};
		struct rs_instance_desc d = {.mesh = sphere};
		make_transform(tilt, 0.3 * i, scale, move, d.transform);
		assert_int_equal(rs_scene_add_instance(scene, &d, NULL, NULL), RS_OK);
	}
	const double eye[3] = {far[0] + 2.5, far[1] + 2.5, far[2] + 14.0};
	compare_walks(scene, eye, 120);
	rs_scene_destroy(&scene);
}

/* A cube room of six instanced walls of one quad prototype (one face mirrored, the room
 * turned about a generic axis): no ray from inside escapes, no interior point is in shadow. */
static void room_of_instanced_walls_is_closed(void **state)
{
	struct rs_scene *scene = new_scene();
	const double quad[4 * 3] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
	const uint32_t qi[6] = {0, 1, 2, 0, 2, 3};
	struct rs_mesh_desc mesh = {
	    .positions_f64 = quad, .vertex_count = 4, .indices = qi, .triangle_count = 2};
	uint32_t wall;
	assert_int_equal(rs_scene_add_prototype(scene, &mesh, &wall, NULL), RS_OK);
	/* wall k: the quad's x, y, z axes onto these world columns (exact +-1 permutations) */
	const double faces[6][3][4] = {
	    {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 1}},
	    {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, -1, -1}},
	    {{0, 0, 1, 1}, {1, 0, 0, 0}, {0, 1, 0, 0}},
	    {{0, 0, -1, -1}, {0, 1, 0, 0}, {1, 0, 0, 0}},
	    {{0, 1, 0, 0}, {0, 0, 1, 1}, {1, 0, 0, 0}},
	    {{1, 0, 0, 0}, {0, 0, -1, -1}, {0, 1, 0, 0}},
	};
	double turn[3][4];
	const double axis[3] = {0.3, 1.0, 0.2}, one[3] = {1, 1, 1}, move[3] = {0.25, -0.5, 3.0};
	make_transform(axis, 0.9, one, move, turn);
	for (int k = 0; k < 6; k++) {
		struct rs_instance_desc d = {.mesh = wall};
		for (int r = 0; r < 3; r++)
			for (int c = 0; c < 4; c++) {
				double v = c == 3 ? turn[r][3] : 0.0;
				for (int j = 0; j < 3; j++)
					v += turn[r][j] * faces[k][j][c];
				d.transform[r][c] = v;
			}
		assert_int_equal(rs_scene_add_instance(scene, &d, NULL, NULL), RS_OK);
	}
	struct rs_packed_instances two;
	assert_int_equal(rs_pack_instances(scene, NULL, NULL, &two, NULL), RS_OK);
	struct rs_packed_two_level merged;
	assert_int_equal(rs_pack_two_level(scene, &two, &merged, NULL), RS_OK);
	uint64_t seed = 12345;
	uint32_t leaks = 0, shadows = 0, merged_leaks = 0, merged_shadows = 0;
	for (int i = 0; i < 20000; i++) {
		double p[2][3];
		for (int q = 0; q < 2; q++) {
			double local[3];
			for (int a = 0; a < 3; a++) {
				seed = seed * 6364136223846793005ull + 1442695040888963407ull;
				local[a] =
				    1.98 * ((double)(seed >> 11) / 9007199254740992.0) - 0.99;
			}
			for (int r = 0; r < 3; r++)
				p[q][r] = turn[r][0] * local[0] + turn[r][1] * local[1] +
				          turn[r][2] * local[2] + turn[r][3];
		}
		struct rs_ray ray = {.tmin = 0.0, .tmax = INFINITY, .skip_slot = RS_NO_SLOT};
		for (int a = 0; a < 3; a++) {
			ray.origin[a] = p[0][a];
			ray.dir[a] = p[1][a] - p[0][a];
		}
		/* toward an edge or a corner of the room every so often */
		if (i % 4 == 0)
			for (int r = 0; r < 3; r++) {
				const double corner[3] = {i % 8 ? 1.0 : 0.0, 1.0, -1.0};
				ray.dir[r] = turn[r][0] * corner[0] + turn[r][1] * corner[1] +
				             turn[r][2] * corner[2] + turn[r][3] - p[0][r];
			}
		struct rs_instance_hit h;
		struct rs_ray local = ray;
		for (int a = 0; a < 3; a++)
			local.origin[a] -= merged.all.origin[a];
		leaks += !rs_trace_instances_closest(&two, RS_TRIANGLE_WATERTIGHT, &ray, &h, NULL);
		merged_leaks +=
		    !rs_trace_two_level_closest(&merged, RS_TRIANGLE_WATERTIGHT, &local, &h, NULL);
		ray.tmax = local.tmax = 1.0;
		for (int a = 0; a < 3; a++)
			ray.dir[a] = local.dir[a] = p[1][a] - p[0][a];
		shadows += rs_trace_instances_occluded(&two, RS_TRIANGLE_WATERTIGHT, &ray, NULL);
		merged_shadows +=
		    rs_trace_two_level_occluded(&merged, RS_TRIANGLE_WATERTIGHT, &local, NULL);
	}
	assert_int_equal(leaks, 0);
	assert_int_equal(shadows, 0);
	assert_int_equal(merged_leaks, 0);
	assert_int_equal(merged_shadows, 0);
	rs_pack_two_level_free(&merged);
	rs_pack_instances_free(&two);
	rs_scene_destroy(&scene);
}

static void two_level_packing_refuses_what_it_cannot_walk(void **state)
{
	struct rs_scene *scene = new_scene();
	struct rs_packed_instances two;
	struct rs_error err = {0};
	assert_int_equal(rs_pack_instances(scene, NULL, NULL, &two, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "no instances"));
	uint32_t sphere = add_sphere(scene);
	assert_int_equal(
	    rs_scene_add_instance(scene, &(struct rs_instance_desc){.mesh = sphere}, NULL, NULL),
	    RS_OK);
	struct rs_pack_desc wide = {.nodes = RS_PACK_NODES_WIDE4};
	assert_int_equal(rs_pack_instances(scene, NULL, &wide, &two, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "wide4"));
	/* the paper's node format and one order walk the same */
	struct rs_pack_desc paper = {.nodes = RS_PACK_NODES_PAPER, .orders = RS_PACK_ORDERS_SINGLE};
	assert_int_equal(rs_pack_instances(scene, NULL, &paper, &two, &err), RS_OK);
	struct rs_ray ray = {
	    .origin = {0, 0, 5}, .dir = {0, 0, -1}, .tmax = INFINITY, .skip_slot = RS_NO_SLOT};
	struct rs_instance_hit h;
	assert_true(rs_trace_instances_closest(&two, RS_TRIANGLE_WATERTIGHT, &ray, &h, NULL));
	assert_true(h.instance == 0 && h.normal[2] > 0.0);
	/* rays with no defined answer miss, and say so */
	ray.dir[1] = NAN;
	assert_false(rs_trace_instances_closest(&two, RS_TRIANGLE_WATERTIGHT, &ray, &h, NULL));
	assert_true(h.instance == RS_NO_SLOT && h.hit.triangle == RS_NO_SLOT);
	ray.dir[0] = ray.dir[1] = ray.dir[2] = 0.0;
	assert_false(rs_trace_instances_occluded(&two, RS_TRIANGLE_WATERTIGHT, &ray, NULL));
	rs_pack_instances_free(&two);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(transformed_instances_hit_as_baked),
	    cmocka_unit_test(far_from_origin_instances_hit_as_baked),
	    cmocka_unit_test(room_of_instanced_walls_is_closed),
	    cmocka_unit_test(two_level_packing_refuses_what_it_cannot_walk),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
