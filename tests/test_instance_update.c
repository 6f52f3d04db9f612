/* Per-frame instance transforms: rs_scene_set_instance_transform() refuses what
 * rs_scene_add_instance() refuses (and a change of mirroring, and an unknown id) without
 * changing anything, and bakes exactly what add_instance would (positions, normals,
 * indices, bounds); rs_pack_instances_update() gives the TLAS and transforms a fresh
 * rs_pack_instances() of the moved scene gives (same bytes, same hits) and refuses another
 * scene's instances; the CPU renderer's rs_renderer_update_instances() renders what a
 * set_scene of the moved scene renders, from the same scene object or another, and refuses
 * changes other than transforms. (EGL: test_gl_instance_update.) */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_pack.h"
#include "raystream/rs_render.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_trace.h"

#include "test_instances_fixture.h"

#define SIZE 40u

static struct rs_scene *scene_at(uint32_t k)
{
	struct rs_scene *s = fix_scene(k);
	assert_non_null(s);
	return s;
}

/* Every array a packer or tracer reads, and the instance records, byte for byte. */
static void assert_same_scene(const struct rs_scene *a, const struct rs_scene *b)
{
	size_t nv = rs_scene_vertex_count(a), nt = rs_scene_triangle_count(a);
	assert_int_equal(nv, rs_scene_vertex_count(b));
	assert_int_equal(nt, rs_scene_triangle_count(b));
	assert_memory_equal(rs_scene_positions_f64(a), rs_scene_positions_f64(b),
	                    nv * 3 * sizeof(double));
	assert_memory_equal(rs_scene_positions(a), rs_scene_positions(b), nv * 3 * sizeof(float));
	assert_memory_equal(rs_scene_normals(a), rs_scene_normals(b), nv * 3 * sizeof(float));
	assert_memory_equal(rs_scene_indices(a), rs_scene_indices(b), nt * 3 * sizeof(uint32_t));
	size_t ni = rs_scene_instance_count(a);
	assert_int_equal(ni, rs_scene_instance_count(b));
	assert_memory_equal(rs_scene_instances(a), rs_scene_instances(b),
	                    ni * sizeof(struct rs_scene_instance));
	struct rs_bounds ba, bb;
	rs_scene_bounds(a, &ba);
	rs_scene_bounds(b, &bb);
	assert_memory_equal(&ba, &bb, sizeof ba);
}

static void refused_transforms_change_nothing(void **state)
{
	(void)state;
	struct rs_scene *scene = scene_at(0), *same = scene_at(0);
	double bad[6][3][4];
	for (int b = 0; b < 6; b++)
		fix_transform(0, 1, bad[b]);
	bad[0][1][2] = NAN;
	bad[1][2][3] = INFINITY;
	for (int c = 0; c < 3; c++)
		bad[2][2][c] = bad[2][0][c]; /* two equal rows: singular */
	bad[3][0][3] = 1e39;                 /* vertices beyond the float range */
	bad[4][0][0] *= 1e-13;               /* det 1e-13 of the scale cubed: refused as singular */
	bad[4][1][0] *= 1e-13;
	bad[4][2][0] *= 1e-13;
	for (int r = 0; r < 3; r++) /* instance 0 is not mirrored: a mirror is another topology */
		bad[5][r][0] = -bad[5][r][0];
	struct rs_error err;
	for (int b = 0; b < 6; b++) {
		assert_int_equal(rs_scene_set_instance_transform(scene, 0, bad[b], &err),
		                 RS_ERR_BAD_DATA);
		print_message("refused %d: %s\n", b, err.message);
		assert_non_null(strstr(err.message, b == 5 ? "mirror" : "instance"));
		assert_null(strchr(err.message, '\n'));
	}
	double ok[3][4];
	fix_transform(3, 0, ok); /* a mirror for the mirrored instance 3, not for 4 */
	assert_int_equal(rs_scene_set_instance_transform(scene, 4, ok, &err), RS_ERR_BAD_DATA);
	assert_int_equal(rs_scene_set_instance_transform(scene, FIX_INSTANCES, ok, &err),
	                 RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "unknown instance"));
	assert_same_scene(scene, same);
	/* and an accepted one does change it */
	assert_int_equal(rs_scene_set_instance_transform(scene, 3, ok, &err), RS_OK);
	fix_transform(0, 1, ok);
	assert_int_equal(rs_scene_set_instance_transform(scene, 0, ok, &err), RS_OK);
	assert_memory_not_equal(rs_scene_positions_f64(scene), rs_scene_positions_f64(same),
	                        rs_scene_vertex_count(scene) * 3 * sizeof(double));
	rs_scene_destroy(&scene);
	rs_scene_destroy(&same);
}

static void moved_instances_bake_as_added(void **state)
{
	(void)state;
	struct rs_scene *scene = scene_at(0);
	for (uint32_t k = 1; k <= 3; k++) {
		assert_int_equal(fix_move(scene, k), RS_OK);
		struct rs_scene *fresh = scene_at(k);
		assert_same_scene(scene, fresh);
		rs_scene_destroy(&fresh);
	}
	/* bounds follow both ways: far out, then back (the union is formed again) */
	struct rs_bounds before, far, back, far_box;
	rs_scene_bounds(scene, &before);
	double m[3][4];
	fix_transform(5, 3, m);
	m[0][3] += 100.0;
	assert_int_equal(rs_scene_set_instance_transform(scene, 5, m, NULL), RS_OK);
	rs_scene_bounds(scene, &far);
	assert_true(far.hi[0] > before.hi[0] + 90.0);
	fix_transform(5, 3, m);
	assert_int_equal(rs_scene_set_instance_transform(scene, 5, m, NULL), RS_OK);
	rs_scene_bounds(scene, &back);
	assert_memory_equal(&back, &before, sizeof back);
	/* a plain mesh added after the moves counts in the bounds as in a fresh scene's */
	struct rs_scene *fresh = scene_at(3);
	const double away[9] = {-40, 0, 0, -41, 1, 0, -40, 2, 1};
	const uint32_t tri[3] = {0, 1, 2};
	const struct rs_mesh_desc mesh = {
	    .positions_f64 = away, .vertex_count = 3, .indices = tri, .triangle_count = 1};
	assert_int_equal(rs_scene_add_mesh(scene, &mesh, NULL), RS_OK);
	assert_int_equal(rs_scene_add_mesh(fresh, &mesh, NULL), RS_OK);
	assert_same_scene(scene, fresh);
	rs_scene_bounds(scene, &far_box);
	assert_true(far_box.lo[0] == -41.0);
	rs_scene_destroy(&fresh);
	rs_scene_destroy(&scene);
}

static void assert_same_packed(const struct rs_packed *a, const struct rs_packed *b)
{
	assert_int_equal(a->node_count, b->node_count);
	assert_memory_equal(a->origin, b->origin, sizeof a->origin);
	const struct rs_texture *ta[2] = {&a->nodes, &a->triangles},
	                        *tb[2] = {&b->nodes, &b->triangles};
	for (int t = 0; t < 2; t++) {
		assert_int_equal(ta[t]->width, tb[t]->width);
		assert_int_equal(ta[t]->height, tb[t]->height);
		assert_memory_equal(ta[t]->words, tb[t]->words,
		                    (size_t)ta[t]->width * ta[t]->height * 16u);
	}
}

static void pack_update_equals_fresh_pack(void **state)
{
	(void)state;
	struct rs_scene *scene = scene_at(0);
	const struct rs_pack_desc descs[2] = {{0}, {.nodes = RS_PACK_NODES_PAPER, .row_items = 8}};
	for (int d = 0; d < 2; d++) {
		struct rs_packed_instances moved, fresh;
		assert_int_equal(rs_pack_instances(scene, NULL, &descs[d], &moved, NULL), RS_OK);
		struct rs_packed *blas = moved.meshes;
		for (uint32_t k = 1; k <= 4; k++) {
			assert_int_equal(fix_move(scene, k + 4u * (uint32_t)d), RS_OK);
			assert_int_equal(rs_pack_instances_update(&moved, scene, NULL, NULL),
			                 RS_OK);
		}
		assert_ptr_equal(moved.meshes, blas); /* BLASes untouched */
		assert_int_equal(rs_pack_instances(scene, NULL, &descs[d], &fresh, NULL), RS_OK);
		assert_same_packed(&moved.top, &fresh.top);
		assert_int_equal(moved.instance_count, fresh.instance_count);
		assert_memory_equal(moved.to_object, fresh.to_object,
		                    moved.instance_count * sizeof *moved.to_object);
		assert_memory_equal(moved.to_world_normal, fresh.to_world_normal,
		                    moved.instance_count * sizeof *moved.to_world_normal);
		/* same hits on rays through the scene from several eyes */
		struct rs_bounds b;
		rs_scene_bounds(scene, &b);
		uint32_t hits = 0, rays = 0;
		for (int e = 0; e < 3; e++)
			for (uint32_t y = 0; y < 40; y++)
				for (uint32_t x = 0; x < 40; x++) {
					const double eye[3] = {-12.0 + 12.0 * e, 6.0 - 4.0 * e,
					                       15.0};
					struct rs_ray ray = {.tmax = INFINITY,
					                     .skip_slot = RS_NO_SLOT};
					double target[3] = {
					    b.lo[0] + (b.hi[0] - b.lo[0]) * (x + 0.5) / 40.0,
					    b.lo[1] + (b.hi[1] - b.lo[1]) * (y + 0.5) / 40.0,
					    0.5 * (b.lo[2] + b.hi[2])};
					for (int a = 0; a < 3; a++) {
						ray.origin[a] = eye[a];
						ray.dir[a] = target[a] - eye[a];
					}
					struct rs_instance_hit h1, h2;
					bool f1 = rs_trace_instances_closest(
					    &moved, RS_TRIANGLE_WATERTIGHT, &ray, &h1, NULL);
					bool f2 = rs_trace_instances_closest(
					    &fresh, RS_TRIANGLE_WATERTIGHT, &ray, &h2, NULL);
					assert_int_equal(f1, f2);
					rays++;
					if (!f1)
						continue;
					hits++;
					assert_int_equal(h1.hit.triangle, h2.hit.triangle);
					assert_true(h1.hit.t == h2.hit.t);
				}
		assert_true(hits > rays / 4);
		rs_pack_instances_free(&fresh);
		rs_pack_instances_free(&moved);
	}
	rs_scene_destroy(&scene);
}

static void pack_update_refuses_other_instances(void **state)
{
	(void)state;
	struct rs_scene *scene = scene_at(0);
	struct rs_packed_instances packed;
	assert_int_equal(rs_pack_instances(scene, NULL, NULL, &packed, NULL), RS_OK);
	struct rs_packed top = packed.top;
	/* one instance fewer; no plain floor; a plain scene */
	struct rs_scene *fewer = fix_scene_with(0, -1.0, FIX_INSTANCES - 1),
	                *no_floor = fix_scene_with(0, -1.0, 2), *plain = NULL;
	assert_non_null(fewer);
	assert_non_null(no_floor);
	assert_int_equal(rs_scene_create(NULL, &plain, NULL), RS_OK);
	const struct {
		const struct rs_scene *scene;
		const char *says;
	} cases[] = {{fewer, "instance count"}, {no_floor, "loose"}, {plain, "prototypes"}};
	struct rs_error err;
	for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
		assert_int_equal(rs_pack_instances_update(&packed, cases[c].scene, NULL, &err),
		                 RS_ERR_INVALID);
		print_message("%s\n", err.message);
		assert_non_null(strstr(err.message, cases[c].says));
		assert_null(strchr(err.message, '\n'));
		assert_memory_equal(&top, &packed.top, sizeof top); /* unchanged */
	}
	struct rs_packed_instances none = {0};
	assert_int_equal(rs_pack_instances_update(&none, scene, NULL, &err), RS_ERR_INVALID);
	/* and the scene it was made from is taken */
	assert_int_equal(rs_pack_instances_update(&packed, scene, NULL, &err), RS_OK);
	rs_pack_instances_free(&packed);
	rs_scene_destroy(&scene);
	rs_scene_destroy(&fewer);
	rs_scene_destroy(&no_floor);
	rs_scene_destroy(&plain);
}

struct image {
	float rgb[SIZE * SIZE * 3];
	uint32_t tri[SIZE * SIZE];
};

static void render(struct rs_renderer *r, struct image *out)
{
	struct rs_frame f = {.rgb = out->rgb, .triangle = out->tri};
	struct rs_error err;
	if (rs_renderer_render(r, NULL, &f, &err) != RS_OK)
		fail_msg("render: %s", err.message);
}

static void cpu_update_instances_renders_as_set_scene(void **state)
{
	(void)state;
	const struct rs_render_desc d = {.width = SIZE, .height = SIZE, .threads = 2};
	struct rs_renderer *moved = NULL, *other = NULL, *fresh = NULL;
	assert_int_equal(rs_renderer_create_cpu(&d, &moved, NULL), RS_OK);
	assert_int_equal(rs_renderer_create_cpu(&d, &other, NULL), RS_OK);
	assert_int_equal(rs_renderer_create_cpu(&d, &fresh, NULL), RS_OK);
	struct rs_scene *scene = scene_at(0), *s0 = scene_at(0), *s2 = scene_at(2),
	                *target = scene_at(2);
	struct rs_error err;
	/* before set_scene */
	assert_int_equal(rs_renderer_update_instances(moved, scene, &err), RS_ERR_INVALID);
	assert_int_equal(rs_renderer_set_scene(moved, scene, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(other, s0, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(fresh, target, NULL), RS_OK);
	/* the same scene object, moved in place */
	assert_int_equal(fix_move(scene, 1), RS_OK);
	assert_int_equal(rs_renderer_update_instances(moved, scene, &err), RS_OK);
	assert_int_equal(fix_move(scene, 2), RS_OK);
	assert_int_equal(rs_renderer_update_instances(moved, scene, &err), RS_OK);
	/* another scene object of frame 2 */
	assert_int_equal(rs_renderer_update_instances(other, s2, &err), RS_OK);
	const struct rs_render_stats *st = rs_renderer_stats(moved);
	assert_int_equal(st->instance_updates, 2);
	assert_int_equal(st->updates, 2);
	/* the CPU backend walks the scene in two levels and rebuilt only its TLAS */
	assert_false(st->instance_update_baked);
	struct image *a = calloc(1, sizeof *a), *b = calloc(1, sizeof *b),
	             *c = calloc(1, sizeof *c);
	assert_non_null(a);
	assert_non_null(b);
	assert_non_null(c);
	render(moved, a);
	render(other, b);
	render(fresh, c);
	assert_memory_equal(a->tri, c->tri, sizeof a->tri);
	assert_memory_equal(b->tri, c->tri, sizeof b->tri);
	assert_memory_equal(a->rgb, c->rgb, sizeof a->rgb);
	assert_memory_equal(b->rgb, c->rgb, sizeof b->rgb);
	/* the move shows: frame 0's image differs */
	struct rs_renderer *still = NULL;
	assert_int_equal(rs_renderer_create_cpu(&d, &still, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(still, s0, NULL), RS_OK);
	render(still, b);
	assert_memory_not_equal(b->tri, c->tri, sizeof b->tri);
	rs_renderer_destroy(&still);
	free(a);
	free(b);
	free(c);
	rs_renderer_destroy(&moved);
	rs_renderer_destroy(&other);
	rs_renderer_destroy(&fresh);
	rs_scene_destroy(&scene);
	rs_scene_destroy(&s0);
	rs_scene_destroy(&s2);
	rs_scene_destroy(&target);
}

/* Two identical prototypes and three instances; instance 2 of prototype `proto2`; or, with
 * `baked`, the same triangles added as plain meshes (the same topology either way). */
static struct rs_scene *twin_scene(const struct rs_scene *from, uint32_t proto2, bool baked)
{
	struct rs_scene *s = NULL;
	assert_int_equal(rs_scene_create(NULL, &s, NULL), RS_OK);
	const struct rs_material m = {.diffuse = {0.5f, 0.5f, 0.5f}};
	assert_int_equal(rs_scene_add_material(s, &m, NULL, NULL), RS_OK);
	struct rs_mesh_desc proto;
	rs_scene_prototype_mesh(from, 0, &proto);
	proto.material = 0;
	assert_int_equal(rs_scene_add_prototype(s, &proto, NULL, NULL), RS_OK);
	assert_int_equal(rs_scene_add_prototype(s, &proto, NULL, NULL), RS_OK);
	for (uint32_t i = 0; i < 3; i++) {
		struct rs_instance_desc d = {.mesh = i == 2 ? proto2 : 0};
		fix_transform(i, 0, d.transform);
		d.transform[0][0] = fabs(d.transform[0][0]); /* none mirrored */
		if (!baked) {
			assert_int_equal(rs_scene_add_instance(s, &d, NULL, NULL), RS_OK);
			continue;
		}
		/* the triangles add_instance would bake, as a plain mesh */
		struct rs_scene *tmp = NULL;
		assert_int_equal(rs_scene_create(NULL, &tmp, NULL), RS_OK);
		assert_int_equal(rs_scene_add_material(tmp, &m, NULL, NULL), RS_OK);
		assert_int_equal(rs_scene_add_prototype(tmp, &proto, NULL, NULL), RS_OK);
		d.mesh = 0;
		assert_int_equal(rs_scene_add_instance(tmp, &d, NULL, NULL), RS_OK);
		struct rs_mesh_desc mesh = {.positions_f64 = rs_scene_positions_f64(tmp),
		                            .vertex_count = rs_scene_vertex_count(tmp),
		                            .normals = rs_scene_normals(tmp),
		                            .indices = rs_scene_indices(tmp),
		                            .triangle_count = rs_scene_triangle_count(tmp)};
		assert_int_equal(rs_scene_add_mesh(s, &mesh, NULL), RS_OK);
		rs_scene_destroy(&tmp);
	}
	return s;
}

static void update_instances_refuses_other_changes(void **state)
{
	(void)state;
	struct rs_renderer *r = NULL;
	const struct rs_render_desc d = {.width = 8, .height = 8, .threads = 1};
	assert_int_equal(rs_renderer_create_cpu(&d, &r, NULL), RS_OK);
	struct rs_scene *fix = scene_at(0);
	struct rs_scene *scene = twin_scene(fix, 0, false), *proto1 = twin_scene(fix, 1, false),
	                *baked = twin_scene(fix, 0, true), *again = twin_scene(fix, 0, false);
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
	/* the topology is the same in all three; what differs is the instances */
	assert_int_equal(rs_render_scene_same_topology(scene, proto1, NULL), RS_OK);
	assert_int_equal(rs_render_scene_same_topology(scene, baked, NULL), RS_OK);
	assert_int_equal(rs_renderer_update_instances(r, proto1, &err), RS_ERR_INVALID);
	print_message("%s\n", err.message);
	assert_non_null(strstr(err.message, "prototype"));
	assert_null(strchr(err.message, '\n'));
	assert_int_equal(rs_renderer_update_instances(r, baked, &err), RS_ERR_INVALID);
	print_message("%s\n", err.message);
	assert_non_null(strstr(err.message, "no instances"));
	/* plain triangles that moved: the same topology, but only instances may move */
	struct rs_scene *low = fix_scene_floor(0, -1.5);
	assert_non_null(low);
	assert_int_equal(rs_renderer_set_scene(r, fix, NULL), RS_OK);
	struct rs_scene *fix1 = scene_at(1);
	assert_int_equal(rs_renderer_update_instances(r, low, &err), RS_ERR_INVALID);
	print_message("%s\n", err.message);
	assert_non_null(strstr(err.message, "plain"));
	assert_int_equal(rs_renderer_update_instances(r, fix1, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
	rs_scene_destroy(&low);
	rs_scene_destroy(&fix1);
	/* a topology change is refused as update_vertices refuses it */
	assert_int_equal(rs_renderer_update_instances(r, fix, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "changed"));
	/* the renderer kept its scene through the refusals: it renders and updates */
	float rgb[8 * 8 * 3];
	struct rs_frame f = {.rgb = rgb};
	assert_int_equal(rs_renderer_render(r, NULL, &f, &err), RS_OK);
	assert_int_equal(rs_renderer_update_instances(r, again, &err), RS_OK);
	assert_int_equal(rs_renderer_render(r, NULL, &f, &err), RS_OK);
	/* a plain scene's renderer has no instances to update */
	assert_int_equal(rs_renderer_set_scene(r, baked, NULL), RS_OK);
	assert_int_equal(rs_renderer_update_instances(r, scene, &err), RS_ERR_INVALID);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&fix);
	rs_scene_destroy(&scene);
	rs_scene_destroy(&proto1);
	rs_scene_destroy(&baked);
	rs_scene_destroy(&again);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(refused_transforms_change_nothing),
	    cmocka_unit_test(moved_instances_bake_as_added),
	    cmocka_unit_test(pack_update_equals_fresh_pack),
	    cmocka_unit_test(pack_update_refuses_other_instances),
	    cmocka_unit_test(cpu_update_instances_renders_as_set_scene),
	    cmocka_unit_test(update_instances_refuses_other_changes),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
