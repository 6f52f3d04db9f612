/* The CPU reference renderer walks an instanced scene in two levels on the merged layout the
 * kernels read (rs_pack_two_level, docs/bvh.md "Instances on the GPU"): Cow17i renders as
 * the flattened Cow17 (same triangle on >= 99.99 % of pixels, >= 60 dB) in a tenth of the
 * bytes; --instances flatten renders it exactly as Cow17 (same counts); two-level is refused
 * where it cannot be walked. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_image.h"
#include "raystream/rs_render.h"
#include "raystream/rs_scenegen.h"

#define SIZE 80u

struct image {
	float rgb[SIZE * SIZE * 3];
	uint32_t triangle[SIZE * SIZE];
	uint64_t boxes, triangles;
};

static struct rs_scene *build(const char *name)
{
	struct rs_scenegen_desc desc;
	struct rs_scene *scene = NULL;
	assert_int_equal(rs_scenegen_parse(name, &desc, NULL), RS_OK);
	assert_int_equal(rs_scenegen_build(&desc, &scene, NULL), RS_OK);
	return scene;
}

static void render(struct rs_render_desc desc, const struct rs_scene *scene, struct image *out)
{
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(&desc, &r, NULL), RS_OK);
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("set_scene: %s", err.message);
	struct rs_frame frame = {.rgb = out->rgb, .triangle = out->triangle};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, NULL), RS_OK);
	out->boxes = rs_renderer_stats(r)->box_tests;
	out->triangles = rs_renderer_stats(r)->triangle_tests;
	rs_renderer_destroy(&r);
}

static void same_frame(const char *what, const struct image *a, const struct image *b)
{
	size_t same = 0, hits = 0;
	for (size_t i = 0; i < SIZE * SIZE; i++) {
		same += a->triangle[i] == b->triangle[i];
		hits += a->triangle[i] != RS_NO_SLOT;
	}
	struct rs_image_diff d;
	rs_image_compare(a->rgb, b->rgb, SIZE, SIZE, 3, 1.0, 1.0 / 255.0, &d);
	print_message("%s: %zu of %u pixels hit, %zu the same triangle, %.1f dB\n", what, hits,
	              SIZE * SIZE, same, d.psnr_db);
	assert_true(hits > SIZE * SIZE / 4);
	assert_true((double)same >= 0.9999 * SIZE * SIZE);
	assert_true(d.psnr_db >= 60.0);
}

static void cow17i_two_level_renders_as_cow17(void **state)
{
	static struct image flat, two, baked;
	struct rs_scene *s_flat = build("cow17"), *s_inst = build("cow17i");
	struct rs_render_desc desc = {
	    .width = SIZE, .height = SIZE, .passes = 2, .lights = 2, .counters = true};
	render(desc, s_flat, &flat);
	render(desc, s_inst, &two); /* auto: two levels */
	same_frame("cpu cow17i two-level vs cow17", &two, &flat);
	desc.instances = RS_INSTANCES_FLATTEN;
	render(desc, s_inst, &baked);
	same_frame("cpu cow17i flattened vs cow17", &baked, &flat);
	print_message("box/triangle tests: cow17 %llu/%llu, cow17i two-level %llu/%llu\n",
	              (unsigned long long)flat.boxes, (unsigned long long)flat.triangles,
	              (unsigned long long)two.boxes, (unsigned long long)two.triangles);
	/* flattened is the very same tree; two levels count both levels' tests */
	assert_true(baked.boxes == flat.boxes && baked.triangles == flat.triangles);
	assert_true(two.boxes != flat.boxes && two.boxes > 0 && two.triangles > 0);
	rs_scene_destroy(&s_flat);
	rs_scene_destroy(&s_inst);
}

static void cow17i_merged_is_a_tenth_of_cow17(void **state)
{
	struct rs_scene *s_flat = build("cow17"), *s_inst = build("cow17i");
	struct rs_render_accel flat, two;
	assert_int_equal(rs_render_accel_build(s_flat, NULL, NULL, &flat, NULL), RS_OK);
	assert_int_equal(rs_render_accel_build_two_level(s_inst, NULL, NULL, &two, NULL), RS_OK);
	size_t a = rs_pack_bytes(&flat.packed), b = rs_pack_two_level_bytes(&two.two_level);
	print_message("cow17 textures %zu bytes, cow17i merged two-level %zu bytes (%.4f); TLAS "
	              "rows + instances %zu bytes\n",
	              a, b, (double)b / (double)a, two.two_level.top_bytes);
	assert_true(b * 10 <= a);
	assert_true(two.two_level.top_bytes < b / 10);
	rs_render_accel_free(&flat);
	rs_render_accel_free(&two);
	rs_scene_destroy(&s_flat);
	rs_scene_destroy(&s_inst);
}

static bool same_texture(const struct rs_texture *a, const struct rs_texture *b)
{
	return a->width == b->width && a->height == b->height &&
	       !memcmp(a->texels, b->texels, (size_t)a->width * a->height * 16u);
}

/* An instance update rewrites the merged layout in place into a fresh packing's bytes. */
static void instance_update_equals_a_fresh_packing(void **state)
{
	struct rs_scene *s0 = NULL, *s5 = NULL;
	assert_int_equal(rs_scenegen_load_frame("cow17i", 0, 0, &s0, NULL), RS_OK);
	assert_int_equal(rs_scenegen_load_frame("cow17i", 5, 0, &s5, NULL), RS_OK);
	struct rs_render_accel moved, fresh;
	assert_int_equal(rs_render_accel_build_two_level(s0, NULL, NULL, &moved, NULL), RS_OK);
	assert_int_equal(rs_render_accel_build_two_level(s5, NULL, NULL, &fresh, NULL), RS_OK);
	const struct rs_packed *a = &moved.two_level.all, *b = &fresh.two_level.all;
	assert_false(same_texture(&moved.two_level.instances, &fresh.two_level.instances));
	assert_int_equal(rs_render_accel_update_instances(&moved, s5, NULL, NULL), RS_OK);
	assert_true(same_texture(&a->nodes, &b->nodes));
	assert_true(same_texture(&a->triangles, &b->triangles));
	assert_true(same_texture(&a->normals, &b->normals));
	assert_true(same_texture(&moved.two_level.instances, &fresh.two_level.instances));
	assert_memory_equal(a->origin, b->origin, sizeof a->origin);
	assert_memory_equal(moved.packed.origin, b->origin, sizeof a->origin);
	print_message("update: TLAS and instances %zu of %zu bytes\n", moved.two_level.top_bytes,
	              rs_pack_two_level_bytes(&moved.two_level));
	assert_true(moved.two_level.top_bytes * 20 < rs_pack_two_level_bytes(&moved.two_level));
	rs_render_accel_free(&moved);
	rs_render_accel_free(&fresh);
	rs_scene_destroy(&s0);
	rs_scene_destroy(&s5);
}

static void two_level_is_refused_where_it_cannot_be_walked(void **state)
{
	struct rs_scene *s_flat = build("cow5"), *s_inst = build("cow5i");
	struct rs_render_desc desc = {.width = 8, .height = 8};
	assert_int_equal(rs_render_desc_set(&desc, "instances", "two-level", NULL), RS_OK);
	assert_int_equal(desc.instances, RS_INSTANCES_TWO_LEVEL);
	char text[32];
	assert_int_equal(rs_render_desc_get(&desc, "instances", text, sizeof text, NULL), RS_OK);
	assert_string_equal(text, "two-level");
	assert_int_equal(rs_render_desc_set(&desc, "instances", "both", NULL), RS_ERR_INVALID);
	bool two = true;
	struct rs_error err;
	assert_int_equal(rs_render_two_level(&desc, s_flat, &two, &err), RS_ERR_UNSUPPORTED);
	assert_non_null(strstr(err.message, "no instances"));
	assert_int_equal(rs_render_two_level(&desc, s_inst, &two, NULL), RS_OK);
	assert_true(two);
	desc.pack.nodes = RS_PACK_NODES_WIDE4;
	assert_int_equal(rs_render_two_level(&desc, s_inst, &two, &err), RS_ERR_UNSUPPORTED);
	assert_non_null(strstr(err.message, "wide4"));
	struct rs_renderer *r = NULL;
	assert_int_equal(rs_renderer_create_cpu(&desc, &r, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, s_inst, NULL), RS_ERR_UNSUPPORTED);
	rs_renderer_destroy(&r);
	/* auto with wide4: flattened, not refused */
	desc.instances = RS_INSTANCES_AUTO;
	assert_int_equal(rs_render_two_level(&desc, s_inst, &two, NULL), RS_OK);
	assert_false(two);
	rs_scene_destroy(&s_flat);
	rs_scene_destroy(&s_inst);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(cow17i_two_level_renders_as_cow17),
	    cmocka_unit_test(cow17i_merged_is_a_tenth_of_cow17),
	    cmocka_unit_test(instance_update_equals_a_fresh_packing),
	    cmocka_unit_test(two_level_is_refused_where_it_cannot_be_walked),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
