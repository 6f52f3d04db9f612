/* Moving vertices between frames (rs_bvh_refit, rs_renderer_update_vertices) on the CPU
 * reference: a refit reproduces the build's boxes when nothing moved and keeps every
 * invariant when things did; a refused refit (NaN, bad tree) leaves the tree as it was; a
 * renderer moved to frame N by updates renders what a set_scene of frame N renders (same
 * hits and colours, counters defined); a topology change is refused with one line and the
 * renderer keeps its scene; the animated scene's frames are a function of the frame number
 * alone (frame N of an updated run equals a fresh set_scene of frame N, bit for bit). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "raystream/rs_render.h"
#include "raystream/rs_scenegen.h"

#define SIZE 48u

static struct rs_scene *frame_scene(const char *name, uint32_t frame)
{
	struct rs_scene *s = NULL;
	struct rs_error err;
	if (rs_scenegen_load_frame(name, frame, 30, &s, &err) != RS_OK)
		fail_msg("%s frame %u: %s", name, frame, err.message);
	return s;
}

struct tree {
	struct rs_bvh_node *nodes;
	uint32_t *order;
	size_t count;
};

static struct tree build(const struct rs_scene *s)
{
	struct tree t = {0};
	size_t tris = rs_scene_triangle_count(s);
	size_t cap = rs_bvh_node_bound(NULL, tris);
	t.nodes = malloc(cap * sizeof *t.nodes);
	t.order = malloc(tris * sizeof *t.order);
	assert_non_null(t.nodes);
	assert_non_null(t.order);
	struct rs_error err;
	assert_int_equal(rs_bvh_build(NULL, rs_scene_positions(s), rs_scene_vertex_count(s),
	                              rs_scene_indices(s), tris, t.nodes, cap, t.order, &t.count,
	                              &err),
	                 RS_OK);
	return t;
}

static enum rs_status refit(struct tree *t, const struct rs_scene *s, const float *positions,
                            struct rs_error *err)
{
	return rs_bvh_refit(t->nodes, t->count, positions, rs_scene_vertex_count(s),
	                    rs_scene_indices(s), t->order, rs_scene_triangle_count(s), err);
}

/* Unmoved: the build's boxes again, to the bit. Moved: every invariant holds, and the
 * refitted tree's cost is what rs_bvh_stats says of it (finite, positive). */
static void refit_keeps_boxes_tight(void **state)
{
	(void)state;
	struct rs_scene *a = frame_scene("animated", 0), *b = frame_scene("animated", 45);
	struct tree t = build(a);
	size_t bytes = t.count * sizeof *t.nodes;
	struct rs_bvh_node *built = malloc(bytes);
	memcpy(built, t.nodes, bytes);
	struct rs_error err;
	assert_int_equal(refit(&t, a, rs_scene_positions(a), &err), RS_OK);
	assert_memory_equal(built, t.nodes, bytes);
	assert_int_equal(refit(&t, b, rs_scene_positions(b), &err), RS_OK);
	assert_int_equal(rs_bvh_check(t.nodes, t.count, rs_scene_positions(b), rs_scene_indices(b),
	                              t.order, rs_scene_triangle_count(b), &err),
	                 RS_OK);
	assert_memory_not_equal(built, t.nodes, bytes);
	struct rs_bvh_stats st;
	rs_bvh_stats(t.nodes, t.count, 1.0f, &st);
	assert_true(isfinite(st.sah_cost) && st.sah_cost > 0.0);
	free(built);
	free(t.nodes);
	free(t.order);
	rs_scene_destroy(&a);
	rs_scene_destroy(&b);
}

/* NaN and infinite vertices, and a corrupt escape, are refused before any box changes. */
static void refit_refuses_bad_input(void **state)
{
	(void)state;
	struct rs_scene *a = frame_scene("animated", 0);
	struct tree t = build(a);
	size_t bytes = t.count * sizeof *t.nodes, n = 3 * rs_scene_vertex_count(a);
	struct rs_bvh_node *built = malloc(bytes);
	float *p = malloc(n * sizeof *p);
	memcpy(built, t.nodes, bytes);
	const float bad[2] = {NAN, INFINITY};
	for (int i = 0; i < 2; ++i) {
		memcpy(p, rs_scene_positions(a), n * sizeof *p);
		p[n / 2] = bad[i];
		struct rs_error err;
		assert_int_equal(refit(&t, a, p, &err), RS_ERR_BAD_DATA);
		assert_non_null(strstr(err.message, "not finite"));
		assert_memory_equal(built, t.nodes, bytes);
	}
	t.nodes[0].escape = 0;
	struct rs_error err;
	assert_int_equal(refit(&t, a, rs_scene_positions(a), &err), RS_ERR_BAD_DATA);
	assert_non_null(strstr(err.message, "escapes"));
	free(p);
	free(built);
	free(t.nodes);
	free(t.order);
	rs_scene_destroy(&a);
}

struct image {
	float rgb[SIZE * SIZE * 3], depth[SIZE * SIZE];
	uint32_t tri[SIZE * SIZE];
	uint64_t boxes, triangles;
};

static struct rs_renderer *cpu(double ratio)
{
	struct rs_render_desc d = {
	    .width = SIZE, .height = SIZE, .threads = 2, .counters = true, .rebuild_ratio = ratio};
	struct rs_renderer *r = NULL;
	struct rs_error err;
	assert_int_equal(rs_renderer_create_cpu(&d, &r, &err), RS_OK);
	return r;
}

static void render(struct rs_renderer *r, struct image *out)
{
	struct rs_frame f = {.rgb = out->rgb, .depth = out->depth, .triangle = out->tri};
	struct rs_error err;
	if (rs_renderer_render(r, NULL, &f, &err) != RS_OK)
		fail_msg("render: %s", err.message);
	const struct rs_render_stats *s = rs_renderer_stats(r);
	assert_true(s->counters_valid);
	out->boxes = s->box_tests;
	out->triangles = s->triangle_tests;
}

/* Frames 0 -> 20 -> 45 by updates against a set_scene of 45: the same image, depth and
 * hits, bit for bit (the CPU reference's closest hit does not depend on the tree), with
 * `ratio` deciding refit or rebuild. */
static void update_chain(const char *name, double ratio, bool want_rebuild)
{
	struct rs_renderer *moved = cpu(ratio), *fresh = cpu(0.0);
	struct rs_scene *s0 = frame_scene(name, 0), *s1 = frame_scene(name, 20);
	struct rs_scene *s2 = frame_scene(name, 45);
	struct rs_error err;
	assert_int_equal(rs_renderer_set_scene(moved, s0, &err), RS_OK);
	assert_int_equal(rs_renderer_update_vertices(moved, s1, &err), RS_OK);
	assert_int_equal(rs_renderer_update_vertices(moved, s2, &err), RS_OK);
	const struct rs_render_stats *st = rs_renderer_stats(moved);
	assert_int_equal(st->updates, 2);
	assert_int_equal(st->update_rebuilds, want_rebuild ? 2 : 0);
	assert_int_equal(st->update_rebuilt, want_rebuild);
	assert_true(st->update_sah_ratio > 0.0 && isfinite(st->update_sah_ratio));
	print_message("%s: refit SAH ratio %.4f, %s\n", name, st->update_sah_ratio,
	              want_rebuild ? "rebuilt" : "refitted");
	assert_int_equal(rs_renderer_set_scene(fresh, s2, &err), RS_OK);
	struct image *a = calloc(1, sizeof *a), *b = calloc(1, sizeof *b);
	render(moved, a);
	render(fresh, b);
	assert_memory_equal(a->tri, b->tri, sizeof a->tri);
	assert_memory_equal(a->depth, b->depth, sizeof a->depth);
	assert_memory_equal(a->rgb, b->rgb, sizeof a->rgb);
	assert_true(a->boxes > 0 && a->triangles > 0);
	if (want_rebuild) /* the same builder on the same positions: the same tree */
		assert_true(a->boxes == b->boxes && a->triangles == b->triangles);
	free(a);
	free(b);
	rs_renderer_destroy(&moved);
	rs_renderer_destroy(&fresh);
	rs_scene_destroy(&s0);
	rs_scene_destroy(&s1);
	rs_scene_destroy(&s2);
}

static void refit_renders_as_set_scene(void **state)
{
	(void)state;
	update_chain("animated", INFINITY, false);
}

static void rebuild_renders_as_set_scene(void **state)
{
	(void)state;
	update_chain("animated", 1e-9, true);
}

static void moved_cow_renders_as_set_scene(void **state)
{
	(void)state;
	update_chain("cow4", 0.0, false);
}

/* A one-mesh scene of two triangles: material colour `red`, indices turned when `turn`. */
static struct rs_scene *pair(float red, bool turn, double dx)
{
	struct rs_scene *s = NULL;
	struct rs_error err;
	assert_int_equal(rs_scene_create(NULL, &s, &err), RS_OK);
	struct rs_material m = {.diffuse = {red, 0.5f, 0.5f}};
	uint32_t id;
	assert_int_equal(rs_scene_add_material(s, &m, &id, &err), RS_OK);
	const double p[12] = {-1 + dx, -1, 0, 1 + dx, -1, 0, 1 + dx, 1, 0, -1 + dx, 1, 0};
	const uint32_t idx[2][6] = {{0, 1, 2, 0, 2, 3}, {1, 2, 0, 0, 2, 3}};
	struct rs_mesh_desc d = {.positions_f64 = p,
	                         .vertex_count = 4,
	                         .indices = idx[turn],
	                         .triangle_count = 2,
	                         .material = id};
	assert_int_equal(rs_scene_add_mesh(s, &d, &err), RS_OK);
	struct rs_light l = {{0, 0, 5}, {1, 1, 1}};
	assert_int_equal(rs_scene_add_light(s, &l, &err), RS_OK);
	return s;
}

/* Each topology change is refused with one line naming it; the renderer keeps rendering
 * its scene; a moved pair is taken. NaN never gets as far: the scene refuses it. */
static void topology_change_refused(void **state)
{
	(void)state;
	struct rs_scene *base = pair(0.5f, false, 0.0), *moved = pair(0.5f, false, 0.25);
	struct rs_scene *recolored = pair(0.9f, false, 0.0), *turned = pair(0.5f, true, 0.0);
	struct rs_scene *other = frame_scene("animated", 0);
	struct rs_renderer *r = cpu(0.0);
	struct rs_error err;
	assert_int_equal(rs_renderer_update_vertices(r, base, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "no scene"));
	assert_int_equal(rs_renderer_set_scene(r, base, &err), RS_OK);
	struct {
		const struct rs_scene *s;
		const char *what;
	} bad[3] = {{recolored, "materials"}, {turned, "indices"}, {other, "triangle count"}};
	for (int i = 0; i < 3; ++i) {
		assert_int_equal(rs_renderer_update_vertices(r, bad[i].s, &err), RS_ERR_INVALID);
		print_message("refused: %s\n", err.message);
		assert_non_null(strstr(err.message, bad[i].what));
		assert_null(strchr(err.message, '\n'));
	}
	struct image *img = calloc(1, sizeof *img);
	render(r, img); /* still the base scene */
	assert_int_equal(rs_renderer_update_vertices(r, moved, &err), RS_OK);
	render(r, img);
	assert_int_equal(rs_renderer_stats(r)->updates, 1);
	free(img);

	double p[12] = {0};
	p[4] = NAN;
	const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
	struct rs_scene *s = NULL;
	assert_int_equal(rs_scene_create(NULL, &s, &err), RS_OK);
	const struct rs_material grey = {.diffuse = {0.5f, 0.5f, 0.5f}};
	uint32_t grey_id;
	assert_int_equal(rs_scene_add_material(s, &grey, &grey_id, &err), RS_OK);
	struct rs_mesh_desc d = {
	    .positions_f64 = p, .vertex_count = 4, .indices = idx, .triangle_count = 2};
	assert_int_not_equal(rs_scene_add_mesh(s, &d, &err), RS_OK);
	assert_non_null(strstr(err.message, "NaN"));
	rs_scene_destroy(&s);

	struct rs_render_desc nan_ratio = {.rebuild_ratio = NAN};
	struct rs_renderer *none = NULL;
	assert_int_equal(rs_renderer_create_cpu(&nan_ratio, &none, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "rebuild ratio"));
	rs_renderer_destroy(&r);
	rs_scene_destroy(&base);
	rs_scene_destroy(&moved);
	rs_scene_destroy(&recolored);
	rs_scene_destroy(&turned);
	rs_scene_destroy(&other);
}

/* Frames are a function of the frame number: built twice, the same positions; a static
 * scene refuses a frame; frame 0 of a moving CowN is the still CowN. */
static void frames_reproducible(void **state)
{
	(void)state;
	struct rs_scene *a = frame_scene("animated", 37), *b = frame_scene("animated", 37);
	struct rs_scene *c = frame_scene("animated", 38);
	size_t n = 3 * rs_scene_vertex_count(a) * sizeof(double);
	assert_memory_equal(rs_scene_positions_f64(a), rs_scene_positions_f64(b), n);
	assert_memory_not_equal(rs_scene_positions_f64(a), rs_scene_positions_f64(c), n);
	struct rs_error err;
	assert_int_equal(rs_render_scene_same_topology(a, c, &err), RS_OK);
	struct rs_bounds ba, bc;
	rs_scene_bounds(a, &ba);
	rs_scene_bounds(c, &bc);
	assert_memory_equal(&ba, &bc, sizeof ba);
	struct rs_scene *s = NULL;
	assert_int_equal(rs_scenegen_load_frame("box", 3, 30, &s, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "does not move"));
	struct rs_scene *still = frame_scene("cow4", 0), *plain = NULL;
	assert_int_equal(rs_scenegen_load("cow4", &plain, &err), RS_OK);
	assert_memory_equal(rs_scene_positions_f64(still), rs_scene_positions_f64(plain),
	                    3 * rs_scene_vertex_count(plain) * sizeof(double));
	rs_scene_destroy(&still);
	rs_scene_destroy(&plain);
	rs_scene_destroy(&a);
	rs_scene_destroy(&b);
	rs_scene_destroy(&c);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(refit_keeps_boxes_tight),
	    cmocka_unit_test(refit_refuses_bad_input),
	    cmocka_unit_test(refit_renders_as_set_scene),
	    cmocka_unit_test(rebuild_renders_as_set_scene),
	    cmocka_unit_test(moved_cow_renders_as_set_scene),
	    cmocka_unit_test(topology_change_refused),
	    cmocka_unit_test(frames_reproducible),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
