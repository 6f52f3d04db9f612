/* rs_render_desc.hits_only: the primary hits and nothing else. On the egl backend one kernel
 * ("primary", primary.glsl: camera ray and closest-hit walk in the fragment) gives the same
 * triangle ids and distances as the shaded frame's first pass, traced and rasterized; the CPU
 * backend names the same triangles; colour, counters and a shaded chain's options are refused
 * or dropped, never silently half-done; its grid-unit box test keeps every hit at extreme
 * scales and on axis-aligned rays. EGL (llvmpipe in CI); skipped without a context. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "test_gl_common.h"
#include "test_gl_field.h"

#define SIZE 96u
#define N (SIZE * SIZE)

/* Render `scene` with `desc` into ids and depth; the frame's kernels' names in `names`. */
static void hits(const char *backend, struct rs_render_desc desc, const struct rs_scene *scene,
                 uint32_t *ids, float *depth, char *names, size_t cap)
{
	if (!desc.width)
		desc.width = desc.height = SIZE;
	struct rs_renderer *r = gl_open(backend, &desc);
	if (!r)
		gl_skip();
	assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
	struct rs_frame frame = {.depth = depth, .triangle = ids};
	assert_int_equal(rs_renderer_render(r, NULL, &frame, NULL), RS_OK);
	const struct rs_render_stats *s = rs_renderer_stats(r);
	names[0] = '\0';
	for (uint32_t k = 0; k < s->kernel_count; ++k) {
		strncat(names, s->kernels[k].name, cap - strlen(names) - 2);
		strncat(names, " ", cap - strlen(names) - 1);
	}
	rs_renderer_destroy(&r);
}

static void same_hits_as_the_shaded_frame(const char *name, enum rs_primary_mode primary,
                                          const char *kernels)
{
	struct rs_scene *scene = gl_scene(name);
	static uint32_t want[N], got[N], cpu[N];
	static float want_t[N], got_t[N], cpu_t[N];
	char names[256];
	struct rs_render_desc shaded = {.passes = 2, .lights = 4, .primary = primary};
	hits("egl", shaded, scene, want, want_t, names, sizeof names);
	struct rs_render_desc only = shaded;
	only.hits_only = true;
	hits("egl", only, scene, got, got_t, names, sizeof names);
	print_message("%s: hits_only ran '%s'\n", name, names);
	assert_string_equal(names, kernels);
	size_t same = 0, covered = 0, cpu_same = 0;
	for (size_t i = 0; i < N; ++i) {
		same += got[i] == want[i] && (got_t[i] == want_t[i] || isinf(want_t[i]));
		covered += got[i] != RS_NO_SLOT;
	}
	/* the CPU backend (which traces its primaries), hits_only too: the same triangles */
	struct rs_renderer *c = NULL;
	only.width = only.height = SIZE;
	only.primary = RS_PRIMARY_TRACE;
	assert_int_equal(rs_renderer_create_cpu(&only, &c, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(c, scene, NULL), RS_OK);
	struct rs_frame frame = {.depth = cpu_t, .triangle = cpu};
	assert_int_equal(rs_renderer_render(c, NULL, &frame, NULL), RS_OK);
	for (size_t i = 0; i < N; ++i)
		cpu_same += cpu[i] == got[i];
	print_message("%s: %zu of %u pixels as the shaded frame's, %zu as the CPU's, %zu hit\n",
	              name, same, N, cpu_same, covered);
	assert_int_equal(same, N); /* the same walk on the same rays: bit for bit */
	assert_true(covered > N / 10);
	assert_true((double)cpu_same >= 0.999 * N);
	rs_renderer_destroy(&c);
	rs_scene_destroy(&scene);
}

static void hits_only_traces_the_shaded_frames_primary_hits_on_box(void **state)
{
	same_hits_as_the_shaded_frame("box", RS_PRIMARY_TRACE, "primary ");
}
static void hits_only_traces_the_shaded_frames_primary_hits_on_cow1(void **state)
{
	same_hits_as_the_shaded_frame("cow1", RS_PRIMARY_TRACE, "primary ");
}
static void hits_only_rasterizes_the_shaded_frames_primary_hits_on_cow1(void **state)
{
	same_hits_as_the_shaded_frame("cow1", RS_PRIMARY_RASTER, "raster resolve ");
}

/* `scene` (freed here) at size x size: the hits-only kernel's ids and distances against the
 * shaded frame's first pass's and the CPU reference's. `exact`: the same as the shaded
 * frame's, bit for bit. Else (rays exactly in a box's face plane, below): where the two
 * differ the hits-only kernel's hit is the nearer (the shaded kernels' R3 test, not this
 * one, skipped a box: with 1/d = 1e30 a ray lying in a face plane gets far = 0 there), and
 * it names the CPU reference's triangle at least as often. Returns the pixels hit. */
static size_t same_as_shaded(const char *what, struct rs_scene *scene, uint32_t size, bool exact)
{
	static uint32_t want[N], got[N], cpu[N];
	static float want_t[N], got_t[N], cpu_t[N];
	char names[256];
	struct rs_render_desc shaded = {.width = size, .height = size, .passes = 1, .lights = 1};
	hits("egl", shaded, scene, want, want_t, names, sizeof names);
	shaded.hits_only = true;
	hits("egl", shaded, scene, got, got_t, names, sizeof names);
	struct rs_renderer *c = NULL;
	assert_int_equal(rs_renderer_create_cpu(&shaded, &c, NULL), RS_OK);
	assert_int_equal(rs_renderer_set_scene(c, scene, NULL), RS_OK);
	struct rs_frame frame = {.depth = cpu_t, .triangle = cpu};
	assert_int_equal(rs_renderer_render(c, NULL, &frame, NULL), RS_OK);
	rs_renderer_destroy(&c);
	size_t same = 0, nearer = 0, covered = 0, got_cpu = 0, want_cpu = 0;
	size_t n = (size_t)size * size;
	for (size_t i = 0; i < n; ++i) {
		bool eq = got[i] == want[i] && (got_t[i] == want_t[i] || isinf(want_t[i]));
		same += eq;
		nearer += !eq && got[i] != RS_NO_SLOT && got_t[i] < want_t[i];
		covered += got[i] != RS_NO_SLOT;
		got_cpu += got[i] == cpu[i];
		want_cpu += want[i] == cpu[i];
	}
	print_message("%s: %zu of %zu pixels as the shaded frame's (%zu nearer), %zu as the "
	              "CPU's (shaded %zu), %zu hit\n",
	              what, same, n, nearer, got_cpu, want_cpu, covered);
	assert_int_equal(same + (exact ? 0 : nearer), n);
	assert_true(got_cpu >= want_cpu);
	rs_scene_destroy(&scene);
	return covered;
}

/* The hits-only kernel tests compact boxes in grid units (common.glsl rs_box_grid), the
 * shaded kernels R3's slab: the same hits wherever the grid test's rounding could matter —
 * tiny, huge, far from the origin, flat; and looking straight down an axis at an odd size,
 * where the centre row's and column's rays have a zero direction component (1/d = 1e30)
 * and run along box faces: at scale 1 the grid bound stays finite, at 1e7 it does not and
 * every box of that axis is entered (slower, never wrong). */
static void hits_only_grid_boxes_keep_the_hits_far_tiny_huge_flat_and_axis_aligned(void **state)
{
	const double zero[3] = {0, 0, 0}, far[3] = {1e6, -1e6, 1e6}, mid[3] = {123.5, 7, -40};
	const size_t quarter = 64 * 64 / 4;
	assert_true(same_as_shaded("field", field(1.0, zero, false, 64), 64, true) > quarter);
	assert_true(same_as_shaded("field 1e-3", field(1e-3, zero, false, 64), 64, true) > quarter);
	assert_true(same_as_shaded("field 1e4", field(1e4, zero, false, 64), 64, true) > quarter);
	assert_true(same_as_shaded("field at 1e6", field(1.0, far, false, 64), 64, true) > quarter);
	assert_true(same_as_shaded("flat field", field(1.0, mid, true, 64), 64, true) >
	            64 * 64 / 16);
	const double scales[2] = {1.0, 1e7};
	for (int k = 0; k < 2; k++) {
		struct rs_scene *scene = field(scales[k], zero, false, 95);
		const double eye[3] = {0, 12 * scales[k], 0};
		fx_camera(scene, eye, zero,
		          95); /* straight down -y: d.x, d.z = 0 on the centre lines */
		char what[64];
		snprintf(what, sizeof what, "field %g seen along -y, 95 x 95", scales[k]);
		assert_true(same_as_shaded(what, scene, 95, false) > 95 * 95 / 4);
	}
}

static void hits_only_refuses_colour_and_counters(void **state)
{
	struct rs_render_desc desc = {.width = 8, .height = 8, .hits_only = true, .counters = true};
	struct rs_renderer *r = NULL;
	struct rs_error err = {0};
	assert_int_equal(rs_renderer_open("egl", &desc, &r, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "hits_only"));
	assert_null(r);
	desc.counters = false;
	desc.shadows = RS_SHADOW_MAP;
	desc.passes = 3;
	r = gl_open("egl", &desc);
	if (!r)
		gl_skip();
	/* nothing shades: one segment, no shadow maps to capture */
	assert_int_equal(rs_renderer_desc(r)->passes, 1);
	assert_int_equal(rs_renderer_desc(r)->shadows, RS_SHADOW_RAYS);
	struct rs_scene *scene = gl_scene("box");
	assert_int_equal(rs_renderer_set_scene(r, scene, NULL), RS_OK);
	static float rgb[8 * 8 * 3];
	static uint8_t rgba8[8 * 8 * 4];
	struct rs_frame with_rgb = {.rgb = rgb}, with_rgba8 = {.rgba8 = rgba8};
	assert_int_equal(rs_renderer_render(r, NULL, &with_rgb, &err), RS_ERR_INVALID);
	assert_non_null(strstr(err.message, "no colour"));
	assert_int_equal(rs_renderer_render(r, NULL, &with_rgba8, &err), RS_ERR_INVALID);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(hits_only_traces_the_shaded_frames_primary_hits_on_box),
	    cmocka_unit_test(hits_only_traces_the_shaded_frames_primary_hits_on_cow1),
	    cmocka_unit_test(hits_only_rasterizes_the_shaded_frames_primary_hits_on_cow1),
	    cmocka_unit_test(
	        hits_only_grid_boxes_keep_the_hits_far_tiny_huge_flat_and_axis_aligned),
	    cmocka_unit_test(hits_only_refuses_colour_and_counters),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
