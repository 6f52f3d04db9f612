/* The GLES two-level walk (docs/gles.md "Instances"): an instanced scene uploaded as one BLAS
 * per prototype and a TLAS merged into the same textures, walked by the kernels with the ray
 * in each instance's frame. Cow17i renders as the flattened Cow17 on EGL on every chain
 * (same triangle on >= 99.99 % of pixels, >= 60 dB) from <= 1/10 of the uploaded bytes, and
 * its hit numbers equal the CPU reference's two-level walk within 0.05 % (as test_gl_instances
 * allows flattened Cow17); rotated, scaled, non-uniformly scaled, mirrored and far-from-origin
 * instances render as the same geometry baked, as do prototypes modelled at 1e21 or 1e-22
 * units; a closed room of instanced walls leaks no
 * pixel; two levels are refused, in one line, where a raster pass would need world triangles.
 * EGL; skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"
#include "test_instances_shapes.h"

#define SIZE 64u
#include "test_gl_same_frame.h"

static void cow17i_two_level_renders_as_cow17_on_every_chain(void **state)
{
	static struct image flat_cpu, two_cpu, flat_gl, two_gl;
	struct rs_scene *flat = gl_scene("cow17"), *inst = gl_scene("cow17i");
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 1,
	                              .counters = true,
	                              .instances = RS_INSTANCES_TWO_LEVEL};
	desc.instances = RS_INSTANCES_AUTO; /* the flattened scene has none */
	render("cpu", desc, flat, &flat_cpu);
	bool have = render("egl", desc, flat, &flat_gl);
	desc.instances = RS_INSTANCES_TWO_LEVEL;
	render("cpu", desc, inst, &two_cpu);
	if (!have) {
		rs_scene_destroy(&flat);
		rs_scene_destroy(&inst);
		gl_skip();
	}
	same_frame("cpu cow17i two-level vs cpu cow17", &two_cpu, &flat_cpu);
	static const char *const names[3] = {"fused", "separate", "paper"};
	for (int chain = 0; chain < 3; chain++) {
		desc.chain = (enum rs_kernel_chain)chain;
		/* the fused chain runs without counters only (gles_plan.c) */
		desc.counters = chain != RS_CHAIN_FUSED;
		assert_true(render("egl", desc, inst, &two_gl));
		char what[64];
		snprintf(what, sizeof what, "egl %s cow17i two-level vs egl cow17", names[chain]);
		assert_true(same_frame(what, &two_gl, &flat_gl) > SIZE * SIZE / 4);
		if (!desc.counters)
			continue;
		print_message(
		    "%s: boxes %llu gpu, %llu cpu; triangles %llu gpu, %llu cpu\n", names[chain],
		    (unsigned long long)two_gl.boxes, (unsigned long long)two_cpu.boxes,
		    (unsigned long long)two_gl.triangles, (unsigned long long)two_cpu.triangles);
		assert_true(two_cpu.boxes > 0 && two_cpu.boxes != flat_cpu.boxes);
		assert_true(near_count(two_gl.boxes, two_cpu.boxes));
		assert_true(near_count(two_gl.triangles, two_cpu.triangles));
	}
	print_message("uploaded: cow17 %llu bytes, cow17i two-level %llu bytes (%.4f)\n",
	              (unsigned long long)flat_gl.upload_bytes,
	              (unsigned long long)two_gl.upload_bytes,
	              (double)two_gl.upload_bytes / (double)flat_gl.upload_bytes);
	assert_true(two_gl.upload_bytes > 0 && two_gl.upload_bytes * 10 <= flat_gl.upload_bytes);
	rs_scene_destroy(&flat);
	rs_scene_destroy(&inst);
}

static void look(struct rs_scene *scene, const double eye[3], const double target[3])
{
	struct rs_camera cam = {.eye = {eye[0], eye[1], eye[2]},
	                        .target = {target[0], target[1], target[2]},
	                        .up = {0, 1, 0},
	                        .fov_y_deg = 60.0};
	assert_int_equal(rs_scene_set_camera(scene, &cam, NULL), RS_OK);
	struct rs_light light = {.position = {eye[0] + 1.0, eye[1] + 2.0, eye[2] - 0.5},
	                         .color = {1, 1, 1}};
	assert_int_equal(rs_scene_add_light(scene, &light, NULL), RS_OK);
}

/* Two levels on EGL (in `storage`: the instance texture is a buffer texture with buffer
 * storage, 2D with 2D) against the same scene flattened on EGL; returns the pixels hit. */
static size_t two_level_in_as_baked(const char *what, const struct rs_scene *scene,
                                    struct rs_pack_desc pack, enum rs_scene_storage storage)
{
	static struct image baked, two;
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 2, .pack = pack};
	desc.instances = RS_INSTANCES_FLATTEN;
	if (!render("egl", desc, scene, &baked))
		return 0;
	desc.instances = RS_INSTANCES_TWO_LEVEL;
	desc.scene_storage = storage;
	assert_true(render("egl", desc, scene, &two));
	return same_frame(what, &two, &baked);
}

static size_t two_level_as_baked_with(const char *what, const struct rs_scene *scene,
                                      struct rs_pack_desc pack)
{
	return two_level_in_as_baked(what, scene, pack, RS_SCENE_STORAGE_AUTO);
}

static size_t two_level_as_baked(const char *what, const struct rs_scene *scene)
{
	return two_level_as_baked_with(what, scene, (struct rs_pack_desc){0});
}

/* The paper's node format, and one node order: the same walk over other node texels. */
static void paper_and_single_order_nodes_render_as_baked(void **state)
{
	struct rs_scene *scene = gl_scene("cow5i");
	struct rs_pack_desc paper = {.nodes = RS_PACK_NODES_PAPER};
	struct rs_pack_desc single = {.orders = RS_PACK_ORDERS_SINGLE};
	size_t a = two_level_as_baked_with("egl cow5i paper nodes", scene, paper);
	size_t b = a ? two_level_as_baked_with("egl cow5i one node order", scene, single) : 0;
	rs_scene_destroy(&scene);
	if (!a)
		gl_skip();
	assert_true(a > SIZE * SIZE / 8 && b == a);
}

static void transformed_instances_render_as_baked(void **state)
{
	struct rs_scene *scene = new_scene();
	uint32_t sphere = add_sphere(scene);
	const double x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, tilt[3] = {1, 2, 3};
	struct {
		const double *axis;
		double angle, scale[3], move[3];
	} set[] = {
	    {y, 0.8, {1, 1, 1}, {2.5, 0, 0}},            /* rotated */
	    {tilt, 1.3, {1.5, 1.5, 1.5}, {-3, 0.5, 0}},  /* scaled */
	    {x, 0.4, {2.0, 0.5, 1.0}, {0, 2.5, 0.5}},    /* non-uniformly scaled */
	    {y, 0.0, {-1, 1, 1}, {0, -1.5, 0}},          /* mirrored */
	    {tilt, 2.0, {1.2, -0.7, 0.9}, {3, 2.5, -1}}, /* mirrored, turned, stretched */
	};
	struct rs_material red = {.diffuse = {1, 0.2f, 0.1f}, .specular = 0.5f, .shininess = 20};
	uint32_t m;
	assert_int_equal(rs_scene_add_material(scene, &red, &m, NULL), RS_OK);
	add_floor(scene, -3.0, 0); /* loose triangles: the loose BLAS */
	for (size_t i = 0; i < sizeof set / sizeof set[0]; i++) {
		struct rs_instance_desc d = {
		    .mesh = sphere, .override_material = i % 2, .material = m};
		make_transform(set[i].axis, set[i].angle, set[i].scale, set[i].move, d.transform);
		assert_int_equal(rs_scene_add_instance(scene, &d, NULL, NULL), RS_OK);
	}
	const double eye[3] = {0.3, 4.0, 11.0}, at[3] = {0, 0, 0};
	look(scene, eye, at);
	size_t hits = two_level_as_baked("egl transformed instances", scene);
	size_t hits_2d = hits
	                     ? two_level_in_as_baked("egl transformed instances, 2D storage", scene,
	                                             (struct rs_pack_desc){0}, RS_SCENE_STORAGE_2D)
	                     : 0;
	rs_scene_destroy(&scene);
	if (!hits)
		gl_skip();
	assert_true(hits > SIZE * SIZE / 4);
	assert_int_equal(hits_2d, hits);
}

static void far_from_origin_instances_render_as_baked(void **state)
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
	const double eye[3] = {far[0] + 2.5, far[1] + 2.5, far[2] + 9.0};
	const double at[3] = {far[0] + 2.5, far[1] + 2.5, far[2]};
	look(scene, eye, at);
	size_t hits = two_level_as_baked("egl far-from-origin instances", scene);
	rs_scene_destroy(&scene);
	if (!hits)
		gl_skip();
	assert_true(hits > SIZE * SIZE / 4);
}

/* Prototypes modelled at 1e21 and 1e-14 units (and 1e-22, whose instances' normal matrix
 * has entries of 1e22), each placed by instances that scale it back to a normal world: the
 * fp32 walk in the prototype's frame overflowed or flushed (instances missing: 25 dB) and the
 * normals' length overflowed (41 dB) until rs_pack_instances scaled the BLAS frame and the
 * normal matrix by powers of two (docs/bvh.md "Instances", R7). */
static void prototypes_modelled_at_any_scale_render_as_baked(void **state)
{
	const double units[] = {1e21, 1e-14, 1e-22};
	size_t hits[3] = {0};
	for (size_t k = 0; k < 3; k++) {
		double s = units[k], pos[SPHERE_VERTICES * 3];
		uint32_t idx[SPHERE_TRIANGLES * 3];
		sphere_arrays(pos, idx);
		for (size_t i = 0; i < SPHERE_VERTICES * 3; i++)
			pos[i] =
			    (pos[i] + (i % 3 == 0 ? 3.0 : 0.0)) * s; /* off its own origin too */
		struct rs_mesh_desc mesh = {.positions_f64 = pos,
		                            .vertex_count = SPHERE_VERTICES,
		                            .indices = idx,
		                            .triangle_count = SPHERE_TRIANGLES};
		struct rs_scene *scene = new_scene();
		uint32_t proto;
		assert_int_equal(rs_scene_add_prototype(scene, &mesh, &proto, NULL), RS_OK);
		add_floor(scene, -1.5, 0);
		const double tilt[3] = {1, 2, 3};
		for (int i = 0; i < 4; i++) {
			const double scale[3] = {1.0 / s, 1.0 / s, (i % 2 ? -1.0 : 1.0) / s};
			const double move[3] = {-2.5 * i, 0.3 * i, 0};
			struct rs_instance_desc d = {.mesh = proto};
			make_transform(tilt, 0.5 * i, scale, move, d.transform);
			assert_int_equal(rs_scene_add_instance(scene, &d, NULL, NULL), RS_OK);
		}
		const double eye[3] = {0.3, 4.0, 11.0}, at[3] = {0, 0, 0};
		look(scene, eye, at);
		char what[64];
		snprintf(what, sizeof what, "egl prototype in units of %g", s);
		hits[k] = two_level_as_baked(what, scene);
		rs_scene_destroy(&scene);
		if (!hits[k])
			gl_skip();
	}
	assert_true(hits[0] > SIZE * SIZE / 4);
	assert_int_equal(hits[1], hits[0]);
	assert_int_equal(hits[2], hits[0]);
}

/* A cube room of six instanced walls of one quad (two mirrored), turned about a generic
 * axis, seen from inside: every pixel hits a wall, on EGL as on the CPU. */
static void room_of_instanced_walls_leaks_no_pixel(void **state)
{
	struct rs_scene *scene = new_scene();
	const double quad[4 * 3] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
	const uint32_t qi[6] = {0, 1, 2, 0, 2, 3};
	struct rs_mesh_desc mesh = {
	    .positions_f64 = quad, .vertex_count = 4, .indices = qi, .triangle_count = 2};
	uint32_t wall;
	assert_int_equal(rs_scene_add_prototype(scene, &mesh, &wall, NULL), RS_OK);
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
	/* from near a corner, looking at the opposite one: edges and corners in view */
	double eye[3], at[3];
	const double le[3] = {0.7, 0.6, -0.8}, la[3] = {-1, -1, 1};
	for (int r = 0; r < 3; r++) {
		eye[r] = turn[r][0] * le[0] + turn[r][1] * le[1] + turn[r][2] * le[2] + turn[r][3];
		at[r] = turn[r][0] * la[0] + turn[r][1] * la[1] + turn[r][2] * la[2] + turn[r][3];
	}
	struct rs_camera cam = {.eye = {eye[0], eye[1], eye[2]},
	                        .target = {at[0], at[1], at[2]},
	                        .up = {0, 1, 0},
	                        .fov_y_deg = 100.0};
	assert_int_equal(rs_scene_set_camera(scene, &cam, NULL), RS_OK);
	struct rs_light light = {.position = {move[0], move[1], move[2]}, .color = {1, 1, 1}};
	assert_int_equal(rs_scene_add_light(scene, &light, NULL), RS_OK);
	static struct image cpu, gl;
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .instances = RS_INSTANCES_TWO_LEVEL};
	render("cpu", desc, scene, &cpu);
	bool have = render("egl", desc, scene, &gl);
	size_t hits = have ? same_frame("egl room vs cpu room, two levels", &gl, &cpu) : 0;
	rs_scene_destroy(&scene);
	if (!have)
		gl_skip();
	assert_int_equal(hits, SIZE * SIZE);
}

/* Cow17i's swaying cow moved by rs_renderer_update_instances(): the image of a fresh
 * set_scene of that frame, with only the TLAS and the instance texture sent. */
static void moved_instances_render_as_set_scene_sending_the_tlas_only(void **state)
{
	struct rs_scene *s0 = NULL, *s5 = NULL;
	assert_int_equal(rs_scenegen_load_frame("cow17i", 0, 0, &s0, NULL), RS_OK);
	assert_int_equal(rs_scenegen_load_frame("cow17i", 5, 0, &s5, NULL), RS_OK);
	struct rs_render_desc desc = {.width = SIZE,
	                              .height = SIZE,
	                              .passes = 2,
	                              .lights = 1,
	                              .instances = RS_INSTANCES_TWO_LEVEL};
	struct rs_renderer *moved = gl_open("egl", &desc), *fresh = gl_open("egl", &desc);
	if (!moved || !fresh) {
		rs_renderer_destroy(&moved);
		rs_renderer_destroy(&fresh);
		rs_scene_destroy(&s0);
		rs_scene_destroy(&s5);
		gl_skip();
	}
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(moved, s0, &err), RS_OK);
	uint64_t full = rs_renderer_stats(moved)->upload_bytes;
	if (rs_renderer_update_instances(moved, s5, &err) != RS_OK)
		fail_msg("update: %s", err.message);
	const struct rs_render_stats *st = rs_renderer_stats(moved);
	print_message("update: %llu bytes sent (set_scene %llu), TLAS build %.2f ms\n",
	              (unsigned long long)st->upload_bytes, (unsigned long long)full,
	              st->tlas_build_ms);
	assert_false(st->instance_update_baked);
	assert_true(st->upload_bytes > 17u * RS_PACK_INSTANCE_TEXELS * 16u);
	assert_true(st->upload_bytes * 20 < full);
	/* exactly the TLAS's items and the instance texture (rs_packed_two_level.top_bytes: the
	 * same for any texture size limit) */
	struct rs_render_accel ref;
	assert_int_equal(rs_render_accel_build_two_level(s5, NULL, NULL, &ref, NULL), RS_OK);
	assert_int_equal(st->upload_bytes, ref.two_level.top_bytes);
	rs_render_accel_free(&ref);
	assert_int_equal(rs_renderer_set_scene(fresh, s5, &err), RS_OK);
	static struct image a, b;
	struct rs_frame fa = {.rgb = a.rgb, .triangle = a.triangle};
	struct rs_frame fb = {.rgb = b.rgb, .triangle = b.triangle};
	assert_int_equal(rs_renderer_render(moved, NULL, &fa, NULL), RS_OK);
	assert_int_equal(rs_renderer_render(fresh, NULL, &fb, NULL), RS_OK);
	assert_memory_equal(a.triangle, b.triangle, sizeof a.triangle);
	assert_memory_equal(a.rgb, b.rgb, sizeof a.rgb);
	rs_renderer_destroy(&moved);
	rs_renderer_destroy(&fresh);
	rs_scene_destroy(&s0);
	rs_scene_destroy(&s5);
}

static void two_level_is_refused_with_raster_passes(void **state)
{
	struct rs_scene *inst = gl_scene("cow5i");
	struct rs_render_desc desc = {.width = 16,
	                              .height = 16,
	                              .primary = RS_PRIMARY_RASTER,
	                              .instances = RS_INSTANCES_TWO_LEVEL};
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r) {
		rs_scene_destroy(&inst);
		gl_skip();
	}
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, inst, &err), RS_ERR_UNSUPPORTED);
	print_message("refused: %s\n", err.message);
	assert_non_null(strstr(err.message, "instances=flatten"));
	rs_renderer_destroy(&r);
	/* auto: the flattened scene */
	desc.instances = RS_INSTANCES_AUTO;
	static struct image img;
	assert_true(render("egl", desc, inst, &img));
	rs_scene_destroy(&inst);
}

/* Bytes set_scene uploads for `scene` under `desc` (0: no GL). */
static uint64_t set_scene_bytes(struct rs_render_desc desc, const struct rs_scene *scene)
{
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r)
		return 0;
	struct rs_error err;
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("set_scene: %s", err.message);
	uint64_t bytes = rs_renderer_stats(r)->upload_bytes;
	rs_renderer_destroy(&r);
	return bytes;
}

/* instances=auto on GLES (rs_gles_two_level): a still scene flattened (its walk is faster
 * on llvmpipe), two levels from the first update_instances on (a full set_scene once,
 * then the TLAS only), and two levels from the start where the flattened scene is over
 * the texture limit. */
static void auto_flattens_a_still_scene_and_moves_it_in_two_levels(void **state)
{
	struct rs_scene *s0 = NULL, *s5 = NULL;
	assert_int_equal(rs_scenegen_load_frame("cow17i", 0, 0, &s0, NULL), RS_OK);
	assert_int_equal(rs_scenegen_load_frame("cow17i", 5, 0, &s5, NULL), RS_OK);
	struct rs_render_desc desc = {.width = SIZE, .height = SIZE, .passes = 2, .lights = 1};
	desc.instances = RS_INSTANCES_FLATTEN;
	uint64_t flat = set_scene_bytes(desc, s0);
	desc.instances = RS_INSTANCES_TWO_LEVEL;
	uint64_t two = flat ? set_scene_bytes(desc, s0) : 0;
	desc.instances = RS_INSTANCES_AUTO;
	struct rs_renderer *r = flat ? gl_open("egl", &desc) : NULL;
	if (!r) {
		rs_scene_destroy(&s0);
		rs_scene_destroy(&s5);
		gl_skip();
	}
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(r, s0, &err), RS_OK);
	const struct rs_render_stats *st = rs_renderer_stats(r);
	print_message("auto: set_scene %llu bytes (flattened %llu, two levels %llu)\n",
	              (unsigned long long)st->upload_bytes, (unsigned long long)flat,
	              (unsigned long long)two);
	assert_true(two * 10 < flat);
	assert_int_equal(st->upload_bytes, flat);
	assert_int_equal(rs_renderer_update_instances(r, s5, &err), RS_OK);
	print_message("auto: first update %llu bytes\n", (unsigned long long)st->upload_bytes);
	assert_false(st->instance_update_baked);
	assert_int_equal(st->upload_bytes, two);
	assert_int_equal(rs_renderer_update_instances(r, s0, &err), RS_OK);
	print_message("auto: second update %llu bytes\n", (unsigned long long)st->upload_bytes);
	assert_false(st->instance_update_baked);
	assert_true(st->upload_bytes * 20 < two);
	rs_renderer_destroy(&r);
	/* the flattened triangle texture over the limit, the two-level one within it */
	setenv("RS_GLES_MAX_TEXTURE_SIZE", "512", 1);
	setenv("RS_GLES_MAX_TEXTURE_BUFFER_SIZE", "65536", 1);
	uint64_t limited = set_scene_bytes(desc, s0);
	unsetenv("RS_GLES_MAX_TEXTURE_SIZE");
	unsetenv("RS_GLES_MAX_TEXTURE_BUFFER_SIZE");
	print_message("auto, 512 texels a side: set_scene %llu bytes\n",
	              (unsigned long long)limited);
	assert_true(limited > 0 && limited * 10 < flat);
	rs_scene_destroy(&s0);
	rs_scene_destroy(&s5);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(cow17i_two_level_renders_as_cow17_on_every_chain),
	    cmocka_unit_test(transformed_instances_render_as_baked),
	    cmocka_unit_test(far_from_origin_instances_render_as_baked),
	    cmocka_unit_test(prototypes_modelled_at_any_scale_render_as_baked),
	    cmocka_unit_test(paper_and_single_order_nodes_render_as_baked),
	    cmocka_unit_test(room_of_instanced_walls_leaks_no_pixel),
	    cmocka_unit_test(moved_instances_render_as_set_scene_sending_the_tlas_only),
	    cmocka_unit_test(two_level_is_refused_with_raster_passes),
	    cmocka_unit_test(auto_flattens_a_still_scene_and_moves_it_in_two_levels),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
