/* The CPU backend's options. Texture layout: the same scene renders bit-identically at every
 * row width (the reference walks the layout the kernels sample), a scene over the texture
 * size limit is refused at set_scene naming the limit, impossible limits are refused when the
 * renderer is made. Intersector: a peer's ray queries run under the reference's paths, one
 * query per ray the stats count. */
#include <stdatomic.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_render.h"
#include "test_trace_render_fixture.h"

#define SIZE 32u

/* A mirror floor, a glass block and a row of small boxes (62 triangles), two lights: the
 * paths read nodes, triangles, normals and materials far into every texture. */
static struct rs_scene *shelf(void)
{
	struct rs_scene *scene = fx_scene();
	struct rs_material grey = {
	    .diffuse = {0.6f, 0.5f, 0.4f}, .specular = 0.4f, .shininess = 24};
	struct rs_material mirror = {.diffuse = {0.1f, 0.1f, 0.1f}, .reflectance = 0.7f};
	struct rs_material glass = {
	    .diffuse = {0.1f, 0.1f, 0.1f}, .transmittance = 0.9f, .ior = 1.5f};
	uint32_t g = fx_material(scene, grey), m = fx_material(scene, mirror),
	         t = fx_material(scene, glass);
	fx_quad(scene, 1, 0.0, -4, 4, 0, m);
	const double glo[3] = {-0.6, 0.01, 0.8}, ghi[3] = {0.6, 1.2, 1.4};
	fx_box(scene, glo, ghi, t);
	for (int i = 0; i < 4; ++i) {
		const double lo[3] = {-2.0 + i, 0.01, -1.0},
		             hi[3] = {-1.4 + i, 0.5 + 0.3 * i, -0.4};
		fx_box(scene, lo, hi, g);
	}
	const double eye[3] = {0.5, 2.5, 5.0}, target[3] = {0, 0.4, 0};
	fx_camera(scene, eye, target, SIZE);
	fx_light(scene, 2, 4, 3, 1, 1, 1);
	fx_light(scene, -3, 2, 1, 0.4, 0.5, 0.6);
	return scene;
}

struct frame_out {
	float rgb[SIZE * SIZE * 3];
	float depth[SIZE * SIZE];
	struct rs_render_stats stats;
};

static void render(const struct rs_scene *scene, uint32_t row_items, struct frame_out *out)
{
	struct rs_render_desc d = {.passes = 3, .threads = 2, .pack.row_items = row_items};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(&d, &r, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_OK);
	struct rs_frame frame = {.rgb = out->rgb, .depth = out->depth};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
	out->stats = *rs_renderer_stats(r);
	rs_renderer_destroy(&r);
}

static void row_width_does_not_change_a_pixel(void **state)
{
	struct rs_scene *scene = shelf();
	static struct frame_out want, got;
	render(scene, 0, &want);
	assert_true(want.stats.secondary_rays > 0);
	const uint32_t rows[] = {1, 3, 7, 40};
	for (size_t i = 0; i < sizeof rows / sizeof rows[0]; ++i) {
		render(scene, rows[i], &got);
		assert_memory_equal(want.rgb, got.rgb, sizeof want.rgb);
		assert_memory_equal(want.depth, got.depth, sizeof want.depth);
		assert_int_equal(want.stats.box_tests, got.stats.box_tests);
		assert_int_equal(want.stats.triangle_tests, got.stats.triangle_tests);
		assert_int_equal(want.stats.shadow_rays, got.stats.shadow_rays);
	}
	rs_scene_destroy(&scene);
}

static void accel_packs_with_the_given_row_width(void **state)
{
	struct rs_scene *scene = shelf();
	struct rs_render_accel a;
	struct rs_pack_desc pd = {.row_items = 7};
	assert_int_equal(rs_render_accel_build(scene, NULL, &pd, &a, NULL), RS_OK);
	assert_int_equal(a.packed.row_items, 7);
	assert_int_equal(a.packed.triangles.width, 21);
	assert_int_equal(a.packed.triangles.height, (62 + 6) / 7);
	rs_render_accel_free(&a);
	assert_int_equal(rs_render_accel_build(scene, NULL, NULL, &a, NULL), RS_OK);
	assert_int_equal(a.packed.row_items, 512); /* GLES 3.0's 2048 texels / 3, a power of 2 */
	rs_render_accel_free(&a);
	rs_scene_destroy(&scene);
}

static void scene_over_the_limit_is_refused_at_set_scene(void **state)
{
	struct rs_scene *scene = shelf();
	/* 3 texels a side: one item a row, three rows: 62 triangles cannot fit. */
	struct rs_render_desc d = {.pack.max_texture_size = 3};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(&d, &r, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_LIMIT);
	assert_non_null(strstr(err.message, "texture size limit of 3 texels"));
	assert_null(strchr(err.message, '\n'));
	assert_string_equal(rs_renderer_last_error(r), err.message);
	float rgb[SIZE * SIZE * 3];
	struct rs_frame frame = {.rgb = rgb};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_ERR_INVALID);
	rs_renderer_destroy(&r);
	struct rs_render_accel a;
	struct rs_pack_desc pd = {.max_texture_size = 3};
	assert_int_equal(rs_render_accel_build(scene, NULL, &pd, &a, &err), RS_ERR_LIMIT);
	assert_null(a.nodes); /* zeroed after a failure */
	rs_scene_destroy(&scene);
}

static void impossible_limits_are_refused_up_front(void **state)
{
	const struct rs_render_desc bad[] = {
	    {.pack.max_texture_size = 2},
	    {.pack = {.max_texture_size = 64, .row_items = 22}},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
		struct rs_renderer *r = NULL;
		struct rs_error err = {0};
		assert_int_equal(rs_renderer_create_cpu(&bad[i], &r, &err), RS_ERR_INVALID);
		assert_null(r);
		assert_true(err.message[0] != '\0');
	}
	/* A row width over the default limit: refused once the CPU resolves its 2048. */
	struct rs_scene *scene = shelf();
	struct rs_render_desc wide = {.pack.row_items = 683};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(&wide, &r, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "limit of 2048"));
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

struct counting_peer {
	/* from prepare: the renderer's own textures, with a zero origin because the rays come
	 * in the packed frame already (the walk then sees them bit for bit) */
	struct rs_packed packed;
	atomic_ulong closest, occluded, prepared;
	enum rs_status fail_prepare;
};

static bool peer_closest(void *user, const struct rs_ray *ray, struct rs_hit *hit)
{
	struct counting_peer *p = user;
	atomic_fetch_add(&p->closest, 1);
	return rs_trace_closest(&p->packed, RS_TRIANGLE_WATERTIGHT, ray, hit, NULL);
}

static bool peer_occluded(void *user, const struct rs_ray *ray)
{
	struct counting_peer *p = user;
	atomic_fetch_add(&p->occluded, 1);
	return rs_trace_occluded(&p->packed, RS_TRIANGLE_WATERTIGHT, ray, NULL);
}

static enum rs_status peer_prepare(void *user, const struct rs_packed *packed, struct rs_error *err)
{
	struct counting_peer *p = user;
	atomic_fetch_add(&p->prepared, 1);
	p->packed = *packed;
	memset(p->packed.origin, 0, sizeof p->packed.origin);
	if (p->fail_prepare != RS_OK)
		return rs_error_set(err, p->fail_prepare, "peer: cannot build");
	return RS_OK;
}

static void intersector_answers_every_ray_of_the_reference(void **state)
{
	struct rs_scene *scene = shelf();
	static struct frame_out want;
	render(scene, 0, &want);
	struct counting_peer peer = {0};
	const struct rs_trace_intersector isect = {.closest = peer_closest,
	                                           .occluded = peer_occluded,
	                                           .prepare = peer_prepare,
	                                           .user = &peer};
	struct rs_render_desc d = {.passes = 3, .threads = 2};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu_with(&d, &isect, &r, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_OK);
	assert_int_equal(atomic_load(&peer.prepared), 1);
	static float rgb[SIZE * SIZE * 3], depth[SIZE * SIZE];
	struct rs_frame frame = {.rgb = rgb, .depth = depth};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_OK);
	assert_memory_equal(want.rgb, rgb, sizeof rgb);
	assert_memory_equal(want.depth, depth, sizeof depth);
	const struct rs_render_stats *s = rs_renderer_stats(r);
	assert_int_equal(atomic_load(&peer.closest), s->primary_rays + s->secondary_rays);
	assert_int_equal(atomic_load(&peer.occluded), s->shadow_rays);
	assert_int_equal(s->shadow_rays, want.stats.shadow_rays);
	assert_false(s->counters_valid); /* the peer counts no box tests */
	assert_int_equal(s->box_tests, 0);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

static void intersector_faults_are_reported(void **state)
{
	struct rs_scene *scene = shelf();
	struct counting_peer peer = {.fail_prepare = RS_ERR_NO_MEMORY};
	struct rs_trace_intersector isect = {.closest = peer_closest,
	                                     .occluded = peer_occluded,
	                                     .prepare = peer_prepare,
	                                     .user = &peer};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu_with(NULL, &isect, &r, &err), RS_OK);
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_NO_MEMORY);
	assert_non_null(strstr(err.message, "peer: cannot build"));
	float rgb[SIZE * SIZE * 3];
	struct rs_frame frame = {.rgb = rgb};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, &err), RS_ERR_INVALID);
	rs_renderer_destroy(&r);
	isect.occluded = NULL;
	assert_int_equal(rs_renderer_create_cpu_with(NULL, &isect, &r, &err), RS_ERR_INVALID);
	assert_null(r);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(row_width_does_not_change_a_pixel),
	    cmocka_unit_test(accel_packs_with_the_given_row_width),
	    cmocka_unit_test(scene_over_the_limit_is_refused_at_set_scene),
	    cmocka_unit_test(impossible_limits_are_refused_up_front),
	    cmocka_unit_test(intersector_answers_every_ray_of_the_reference),
	    cmocka_unit_test(intersector_faults_are_reported),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
