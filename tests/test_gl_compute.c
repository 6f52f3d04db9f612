/* Compute kernels (rs_render_desc.kernels = RS_KERNELS_COMPUTE, docs/gles.md "Compute
 * kernels"): the fused chain's passes dispatched as GLES 3.1 compute programs must give the
 * fragment passes' frame bit for bit (float colour, RGBA8 bytes, depth, triangle ids) over
 * every method a fused pass can be: traced and rasterized primaries, one and several
 * passes, shadow rays, maps and none, classic environment maps and inter-reflection, 2D and
 * buffer storage, wide nodes, two levels, an odd frame size and cube faces larger than the
 * frame, faces taken through the readback fallback, vertices moved between frames. Each case also
 * proves the compute programs ran (the frame's kernel timings name "trace compute", never "trace").
 * Where compute cannot run as asked it is refused in one line: the separate and paper chains, and a
 * context without compute shaders (the seam rs__gles_force_no_compute). A counting frame runs the
 * separate chain in fragment passes, as documented, with the same image. EGL (llvmpipe in CI), and
 * OSMesa where the build has it; skipped without a context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../backends/gles/gles_seams.h"
#include "test_gl_common.h"

#define MAX_W 64u
#define MAX_H 64u
#define MAX_PX (MAX_W * MAX_H)

/* One frame of each stage: the float colour with depth and triangle ids, then the RGBA8
 * bytes alone (the fragment chain's last pass writes those itself; compute's display pass). */
struct frame {
	float rgb[MAX_PX * 3], depth[MAX_PX];
	uint32_t tri[MAX_PX];
	uint8_t bytes[MAX_PX * 4];
	struct rs_render_stats stats, stats_bytes;
};

/* The scene's frame 5 (cowN move: rs_scenegen_load_frame), handed over as an update; the
 * renderer holds it until it is destroyed (the caller frees it after). */
static struct rs_scene *move_on(struct rs_renderer *r, const char *scene_name)
{
	struct rs_scene *next = NULL;
	struct rs_error err = {0};
	if (rs_scenegen_load_frame(scene_name, 5, 30, &next, &err) != RS_OK)
		fail_msg("frame 5: %s", err.message);
	if (rs_renderer_update_vertices(r, next, &err) != RS_OK)
		fail_msg("update_vertices: %s", err.message);
	return next;
}

/* `desc` on `scene` with `backend`: both frames of one stage (false: no context). */
static bool frames(const char *backend, struct rs_render_desc desc, enum rs_kernel_stage stage,
                   const struct rs_scene *scene, const char *move, struct frame *f)
{
	desc.kernels = stage;
	struct rs_renderer *r = gl_open(backend, &desc);
	if (!r)
		return false;
	struct rs_error err = {0};
	if (rs_renderer_set_scene(r, scene, &err) != RS_OK)
		fail_msg("set_scene (%s): %s", stage ? "compute" : "fragment", err.message);
	struct rs_scene *moved = move ? move_on(r, move) : NULL;
	gl_render_frame(r, &(struct rs_frame){.rgb = f->rgb, .depth = f->depth, .triangle = f->tri},
	                &f->stats);
	gl_render_frame(r, &(struct rs_frame){.rgba8 = f->bytes}, &f->stats_bytes);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&moved);
	return true;
}

/* The two stages' frames agree bit for bit, the compute one ran compute programs as many
 * times as the fragment one ran fragment passes, and the frame is not black. */
static void compute_as_fragment_on(const char *backend, const char *what,
                                   struct rs_render_desc desc, const char *scene_name,
                                   const char *move)
{
	/* a moving scene's frame 0 as the scenes it moves on from are made (its camera) */
	struct rs_scene *scene = NULL;
	if (move)
		assert_int_equal(rs_scenegen_load_frame(move, 0, 30, &scene, NULL), RS_OK);
	else
		scene = gl_scene(scene_name);
	static struct frame frag, comp;
	memset(&frag, 0, sizeof frag);
	memset(&comp, 0, sizeof comp);
	if (!frames(backend, desc, RS_KERNELS_FRAGMENT, scene, move, &frag) ||
	    !frames(backend, desc, RS_KERNELS_COMPUTE, scene, move, &comp)) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	size_t n = (size_t)desc.width * desc.height, lit = 0, differ = 0;
	for (size_t i = 0; i < 3 * n; ++i) {
		differ += memcmp(&frag.rgb[i], &comp.rgb[i], sizeof(float)) != 0;
		lit += comp.rgb[i] > 0.05f;
	}
	print_message("%s (%s): trace %u, trace compute %u, display %u; %zu of %zu floats "
	              "differ, %zu lit\n",
	              what, backend, gl_calls(&frag.stats, "trace"),
	              gl_calls(&comp.stats, "trace compute"),
	              gl_calls(&comp.stats_bytes, "display"), differ, 3 * n, lit);
	assert_true(gl_calls(&frag.stats, "trace") >= 1);
	assert_int_equal(gl_calls(&comp.stats, "trace compute"), gl_calls(&frag.stats, "trace"));
	assert_int_equal(gl_calls(&comp.stats, "trace"), 0);
	assert_int_equal(gl_calls(&frag.stats, "trace compute"), 0);
	/* bytes only: the compute chain's last pass stores floats, the display pass converts */
	assert_int_equal(gl_calls(&comp.stats_bytes, "display"), 1);
	assert_int_equal(differ, 0);
	assert_memory_equal(frag.depth, comp.depth, n * sizeof(float));
	assert_memory_equal(frag.tri, comp.tri, n * sizeof(uint32_t));
	assert_memory_equal(frag.bytes, comp.bytes, n * 4);
	/* not black: a quarter lit, and primary rays hit; the moved cow1 (frame 5, from its own
	 * frame 0 camera) fills only ~5 % of the view, the rest dark: 1 % there */
	size_t hits = 0, least = move ? n / 100 : n / 4;
	for (size_t i = 0; i < n; ++i)
		hits += isfinite(comp.depth[i]);
	assert_true(lit > least);
	assert_true(hits > n / 100);
	rs_scene_destroy(&scene);
}

static void compute_as_fragment(const char *what, struct rs_render_desc desc,
                                const char *scene_name)
{
	compute_as_fragment_on("egl", what, desc, scene_name, NULL);
}

/* Every method a fused pass can be (test_gl_common.h, gl_fused_cases). */
static void every_fused_method(void **state)
{
	(void)state;
	struct gl_fused_case cases[GL_FUSED_CASES];
	gl_fused_cases(MAX_W, MAX_H, cases);
	for (int i = 0; i < GL_FUSED_CASES; ++i)
		compute_as_fragment(cases[i].what, cases[i].desc, cases[i].scene);
	struct rs_render_desc d = gl_fused_desc(MAX_W, MAX_H, 3);
	d.lights = 0; /* all of them */
	compute_as_fragment("mirrors, 3 passes, all lights", d, "mirrors");
}

static void storage_and_node_layouts(void **state)
{
	(void)state;
	struct rs_render_desc d = gl_fused_desc(MAX_W, MAX_H, 2);
	d.scene_storage = RS_SCENE_STORAGE_2D;
	compute_as_fragment("cow1, 2D storage", d, "cow1");
	d = gl_fused_desc(MAX_W, MAX_H, 2);
	d.pack.nodes = RS_PACK_NODES_WIDE4;
	compute_as_fragment("cow1, wide nodes", d, "cow1");
	d = gl_fused_desc(MAX_W, MAX_H, 2);
	d.instances = RS_INSTANCES_TWO_LEVEL;
	compute_as_fragment("cow5i, two levels", d, "cow5i");
}

/* Cube faces taken through the readback fallback (as where an RGBA16F face is no colour
 * attachment): the compute passes' images read back by glReadPixels after the barrier. */
static void captures_read_back(void **state)
{
	(void)state;
	struct rs_render_desc d = gl_fused_desc(MAX_W, MAX_H, 3);
	d.reflections = RS_REFLECT_INTERREFLECT;
	d.reflection_bounces = 2;
	d.envmap_size = 24;
	rs__gles_force_capture_readback(true);
	compute_as_fragment("mirrors, inter-reflection, faces read back", d, "mirrors");
	rs__gles_force_capture_readback(false);
}

static void moving_scene(void **state)
{
	(void)state;
	compute_as_fragment_on("egl", "cow1, vertices moved", gl_fused_desc(MAX_W, MAX_H, 2),
	                       "cow1", "cow1");
}

static void osmesa_too(void **state)
{
	(void)state;
	if (!rs_renderer_has_backend("osmesa")) {
		print_message("osmesa: not in this build\n");
		return;
	}
	compute_as_fragment_on("osmesa", "box, 2 passes", gl_fused_desc(MAX_W, MAX_H, 2), "box",
	                       NULL);
}

static void refused(struct rs_render_desc desc, const char *needle)
{
	struct rs_scene *scene = gl_scene("box");
	struct rs_renderer *r = gl_open("egl", &desc);
	if (!r) {
		rs_scene_destroy(&scene);
		gl_skip();
	}
	struct rs_error err = {0};
	assert_int_equal(rs_renderer_set_scene(r, scene, &err), RS_ERR_UNSUPPORTED);
	print_message("refused: %s\n", err.message);
	assert_non_null(strstr(err.message, needle));
	assert_null(strchr(err.message, '\n'));
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
}

/* Compute where it cannot run as asked: refused in one line naming why. */
static void refused_where_it_cannot_run(void **state)
{
	(void)state;
	struct rs_render_desc d = gl_fused_desc(MAX_W, MAX_H, 2);
	d.kernels = RS_KERNELS_COMPUTE;
	d.chain = RS_CHAIN_SEPARATE;
	refused(d, "fused chain");
	d.chain = RS_CHAIN_PAPER;
	refused(d, "fused chain");
	d.chain = RS_CHAIN_FUSED;
	rs__gles_force_no_compute(true);
	refused(d, "compute shaders");
	rs__gles_force_no_compute(false);
	/* an unknown stage is refused before any backend */
	d.kernels = (enum rs_kernel_stage)7;
	struct rs_renderer *r = NULL;
	struct rs_error err = {0};
	assert_int_equal(rs_renderer_open("egl", &d, &r, &err), RS_ERR_INVALID);
	assert_null(r);
	assert_non_null(strstr(err.message, "kernel stage"));
}

/* A counting frame runs the separate chain (fragment passes) whatever the stage: the same
 * image and counts as with fragment kernels, and no compute program. */
static void counting_frames_stay_fragment(void **state)
{
	(void)state;
	struct rs_scene *scene = gl_scene("cow1");
	static struct frame f[2];
	memset(f, 0, sizeof f);
	for (int k = 0; k < 2; ++k) {
		struct rs_render_desc d = gl_fused_desc(MAX_W, MAX_H, 2);
		d.counters = true;
		if (!frames("egl", d, (enum rs_kernel_stage)k, scene, NULL, &f[k])) {
			rs_scene_destroy(&scene);
			gl_skip();
		}
		assert_int_equal(gl_calls(&f[k].stats, "trace compute"), 0);
		assert_true(gl_calls(&f[k].stats, "intersect") >= 1);
		assert_true(f[k].stats.counters_valid);
	}
	assert_memory_equal(f[0].rgb, f[1].rgb, sizeof f[0].rgb);
	assert_true(f[0].stats.box_tests == f[1].stats.box_tests);
	rs_scene_destroy(&scene);
}

/* The option as text (the tools' --kernels). */
static void option_text(void **state)
{
	(void)state;
	struct rs_render_desc d = {0};
	char text[32];
	assert_int_equal(rs_render_desc_get(&d, "kernels", text, sizeof text, NULL), RS_OK);
	assert_string_equal(text, "fragment");
	assert_int_equal(rs_render_desc_set(&d, "kernels", "compute", NULL), RS_OK);
	assert_int_equal(d.kernels, RS_KERNELS_COMPUTE);
	assert_int_equal(rs_render_desc_get(&d, "kernels", text, sizeof text, NULL), RS_OK);
	assert_string_equal(text, "compute");
	struct rs_error err = {0};
	assert_int_equal(rs_render_desc_set(&d, "kernels", "vertex", &err), RS_ERR_INVALID);
	assert_int_equal(d.kernels, RS_KERNELS_COMPUTE); /* a failed parse changes nothing */
	assert_non_null(strstr(err.message, "fragment|compute"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(option_text),
	    cmocka_unit_test(every_fused_method),
	    cmocka_unit_test(storage_and_node_layouts),
	    cmocka_unit_test(captures_read_back),
	    cmocka_unit_test(moving_scene),
	    cmocka_unit_test(osmesa_too),
	    cmocka_unit_test(refused_where_it_cannot_run),
	    cmocka_unit_test(counting_frames_stay_fragment),
	};
	return gl_exit(cmocka_run_group_tests(tests, NULL, NULL));
}
