/*
 * raystream-peer-tmb: primary rays against three-mesh-bvh's GLSL traversal on the same driver
 * (docs/benchmarks.md, "Primary rays against three-mesh-bvh"; tools/peer-three-mesh-bvh.sh
 * runs it as a user types it).
 *   --scene S --mesh-out FILE   the scene's triangles for build_bvh.mjs (RSMESH1 layout below)
 *   --scene S --bvh DIR         time our primary rays and the peer's on the same camera rays,
 *                               alternately, frame for frame, and check both hit the
 *                               triangles the CPU reference hits, pixel for pixel.
 * Ours: the egl backend with rs_render_desc.hits_only, the primary closest hits and nothing
 * else: one kernel ("primary") that makes each pixel's camera ray and walks the BVH, its
 * time glFinish'ed by the renderer. Beside it, as a second figure, the separate chain's
 * raygen + intersect kernels (1 pass, shadow maps: no shadow rays), whose ray texture round
 * trip the hits-only kernel does not make. Theirs: one draw of their bvhIntersectFirstHit per
 * pixel, camera ray made in the shader (peer_gl.c), glFinish'ed. Each writes the closest hit
 * only. One line of figures on stdout.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "peer_gl.h"
#include "raystream/rs_cli.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_scenegen.h"
#include "tool_common.h"

#define PEER_MAX_REPEATS 64

struct peer_options {
	const char *scene, *mesh_out, *bvh;
	uint32_t repeats;
	struct rs_render_desc render;
};

/* "RSMESH1\0", uint32 vertex count, uint32 triangle count, float32 xyz per vertex, uint32
 * abc per triangle, little-endian as the machine writes it (build_bvh.mjs reads LE). */
static enum rs_status write_mesh(const struct rs_scene *scene, const char *path,
                                 struct rs_error *err)
{
	uint32_t counts[2] = {(uint32_t)rs_scene_vertex_count(scene),
	                      (uint32_t)rs_scene_triangle_count(scene)};
	char tmp[4096];
	snprintf(tmp, sizeof tmp, "%s.tmp", path);
	FILE *f = fopen(tmp, "wb");
	bool ok = f && fwrite("RSMESH1", 1, 8, f) == 8 && fwrite(counts, 4, 2, f) == 2 &&
	          fwrite(rs_scene_positions(scene), 12, counts[0], f) == counts[0] &&
	          fwrite(rs_scene_indices(scene), 12, counts[1], f) == counts[1];
	if (f && fclose(f) != 0)
		ok = false;
	if (!ok || rename(tmp, path) != 0) {
		remove(tmp);
		return rs_error_set(err, RS_ERR_IO, "%s: cannot write", path);
	}
	printf("wrote %s\n", path);
	return RS_OK;
}

static enum rs_status read_slots(const char *dir, size_t triangles, uint32_t *out,
                                 struct rs_error *err)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/slots.bin", dir);
	FILE *f = fopen(path, "rb");
	size_t n = f ? fread(out, 4, triangles, f) : 0;
	bool extra = f && fgetc(f) != EOF;
	if (f)
		fclose(f);
	if (n != triangles || extra)
		return rs_error_set(err, RS_ERR_INVALID, "%s: not %zu triangle slots", path,
		                    triangles);
	for (size_t i = 0; i < triangles; ++i)
		if (out[i] >= triangles)
			return rs_error_set(err, RS_ERR_INVALID, "%s: slot %zu names triangle %u",
			                    path, i, out[i]);
	return RS_OK;
}

/* The summed times of the `want` kernels named a and b (b NULL: one kernel) of the frame
 * just rendered: hits_only's "primary", the separate chain's "raygen" + "intersect". */
static enum rs_status kernels_ms(const struct rs_renderer *r, const char *a, const char *b,
                                 double *out, struct rs_error *err)
{
	const struct rs_render_stats *s = rs_renderer_stats(r);
	int found = 0, want = b ? 2 : 1;
	*out = 0.0;
	for (uint32_t k = 0; k < s->kernel_count; ++k)
		if (!strcmp(s->kernels[k].name, a) || (b && !strcmp(s->kernels[k].name, b))) {
			if (s->kernels[k].calls != 1)
				return rs_error_set(err, RS_ERR_INVALID,
				                    "kernel %s ran %u times, not once",
				                    s->kernels[k].name, s->kernels[k].calls);
			*out += s->kernels[k].ms;
			++found;
		}
	return found == want
	           ? RS_OK
	           : rs_error_set(err, RS_ERR_UNSUPPORTED, "the renderer has no %s%s%s kernel", a,
	                          b ? " and " : "", b ? b : "");
}

static double agreement(const uint32_t *a, const uint32_t *b, size_t n)
{
	size_t same = 0;
	for (size_t i = 0; i < n; ++i)
		same += a[i] == b[i];
	return 100.0 * (double)same / (double)n;
}

struct peer_run {
	struct rs_scene *scene;
	struct rs_renderer *ours, *sep, *cpu;
	struct peer_gl *gl;
	uint32_t *cpu_ids, *our_ids, *sep_ids, *their_ids, *slots;
	double ours_ms[PEER_MAX_REPEATS], sep_ms[PEER_MAX_REPEATS], theirs_ms[PEER_MAX_REPEATS];
};

static enum rs_status compare(const struct peer_options *o, struct peer_run *p,
                              struct rs_error *err)
{
	struct rs_render_desc d = o->render;
	uint32_t w = d.width, h = d.height;
	size_t n = (size_t)w * h, tris = rs_scene_triangle_count(p->scene);
	p->cpu_ids = malloc(n * 4);
	p->our_ids = malloc(n * 4);
	p->sep_ids = malloc(n * 4);
	p->their_ids = malloc(n * 4);
	p->slots = malloc(tris * 4 + 4);
	if (!p->cpu_ids || !p->our_ids || !p->sep_ids || !p->their_ids || !p->slots)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory");
	enum rs_status st = read_slots(o->bvh, tris, p->slots, err);
	if (st != RS_OK)
		return st;
	struct rs_render_desc ref = {.width = w, .height = h, .passes = 1, .lights = 1};
	struct rs_frame cpu_frame = {.triangle = p->cpu_ids}, our_frame = {.triangle = p->our_ids},
	                sep_frame = {.triangle = p->sep_ids};
	d.passes = 1;
	d.lights = 1;
	struct rs_render_desc hits = d;
	hits.hits_only = true;
	if ((st = rs_renderer_open("egl", &hits, &p->ours, err)) != RS_OK ||
	    (st = rs_renderer_set_scene(p->ours, p->scene, err)) != RS_OK ||
	    (st = rs_render_desc_parse(&d, "chain=separate,shadows=map", err)) != RS_OK ||
	    (st = rs_renderer_open("egl", &d, &p->sep, err)) != RS_OK ||
	    (st = rs_renderer_set_scene(p->sep, p->scene, err)) != RS_OK ||
	    (st = rs_renderer_open("cpu", &ref, &p->cpu, err)) != RS_OK ||
	    (st = rs_renderer_set_scene(p->cpu, p->scene, err)) != RS_OK ||
	    (st = rs_renderer_render(p->cpu, NULL, &cpu_frame, err)) != RS_OK ||
	    (st = peer_gl_create(o->bvh, w, h, &p->gl, err)) != RS_OK)
		return st;
	const char *ours = rs_renderer_stats(p->ours)->renderer, *theirs = peer_gl_renderer(p->gl);
	if (strncmp(ours, theirs, strlen(theirs)) != 0)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "not the same driver: ours '%s', theirs '%s'", ours, theirs);
	struct rs_trace_view view;
	rs_trace_view_init(rs_scene_camera(p->scene), NULL, w, h, &view);
	double ms;
	/* a warm-up frame each (shader compilation happens at first draw), then alternately */
	if ((st = rs_renderer_render(p->ours, NULL, &our_frame, err)) != RS_OK ||
	    (st = rs_renderer_render(p->sep, NULL, &sep_frame, err)) != RS_OK ||
	    (st = peer_gl_trace(p->gl, &view, &ms, err)) != RS_OK)
		return st;
	for (uint32_t f = 0; f < o->repeats; ++f)
		if ((st = rs_renderer_render(p->ours, NULL, &our_frame, err)) != RS_OK ||
		    (st = kernels_ms(p->ours, "primary", NULL, &p->ours_ms[f], err)) != RS_OK ||
		    (st = rs_renderer_render(p->sep, NULL, &sep_frame, err)) != RS_OK ||
		    (st = kernels_ms(p->sep, "raygen", "intersect", &p->sep_ms[f], err)) != RS_OK ||
		    (st = peer_gl_trace(p->gl, &view, &p->theirs_ms[f], err)) != RS_OK)
			return st;
	if ((st = peer_gl_read(p->gl, p->their_ids, NULL, err)) != RS_OK)
		return st;
	for (size_t i = 0; i < n; ++i)
		p->their_ids[i] = p->their_ids[i] < tris ? p->slots[p->their_ids[i]]
		                  : p->their_ids[i] == UINT32_MAX
		                      ? RS_NO_SLOT
		                      : (uint32_t)tris; /* never agrees */
	/* per frame pair, their time over ours: the spread of the ratio under load */
	double ratio[PEER_MAX_REPEATS], lo = 1e300, hi = 0.0;
	for (uint32_t f = 0; f < o->repeats; ++f) {
		ratio[f] = p->theirs_ms[f] / p->ours_ms[f];
		lo = ratio[f] < lo ? ratio[f] : lo;
		hi = ratio[f] > hi ? ratio[f] : hi;
	}
	double ours_ms = rs_tool_median(p->ours_ms, o->repeats);
	double theirs_ms = rs_tool_median(p->theirs_ms, o->repeats);
	double sep_ms = rs_tool_median(p->sep_ms, o->repeats);
	char nodes[64];
	rs_tool_nodes_name(&o->render.pack, nodes, sizeof nodes);
	printf(
	    "scene %s size %ux%u rays %zu frames %u ours_ms %.2f theirs_ms %.2f ours_mrays %.2f "
	    "theirs_mrays %.2f ratio %.2f ratio_min %.2f ratio_max %.2f ours_agree %.3f "
	    "theirs_agree %.3f separate_ms %.2f separate_ratio %.2f separate_agree %.3f nodes %s\n"
	    "renderer %s\n",
	    o->scene, w, h, n, o->repeats, ours_ms, theirs_ms, (double)n / (ours_ms * 1000.0),
	    (double)n / (theirs_ms * 1000.0), theirs_ms / ours_ms, lo, hi,
	    agreement(p->our_ids, p->cpu_ids, n), agreement(p->their_ids, p->cpu_ids, n), sep_ms,
	    theirs_ms / sep_ms, agreement(p->sep_ids, p->cpu_ids, n), nodes, theirs);
	return RS_OK;
}

int main(int argc, char **argv)
{
	/* ours walks octant node orders unless --nodes says otherwise: three-mesh-bvh's near
	 * child first at every node (docs/bvh.md "Node orders"), 10 % fewer tests than the
	 * shaded frames' default directional orders on Cow1's primary rays */
	struct peer_options o = {
	    .repeats = 7,
	    .render = {.width = 512, .height = 512, .pack.orders = RS_PACK_ORDERS_OCTANT}};
	const struct rs_cli_option opts[] = {
	    RS_CLI_STRING_OPT("--scene", &o.scene, "SCENE", "the scene (required; not instanced)"),
	    RS_CLI_STRING_OPT("--mesh-out", &o.mesh_out, "FILE",
	                      "write the scene's triangles for build_bvh.mjs and stop"),
	    RS_CLI_STRING_OPT("--bvh", &o.bvh, "DIR",
	                      "three-mesh-bvh's packed BVH (build_bvh.mjs)"),
	    RS_CLI_U32_OPT("--repeats", &o.repeats, 1, PEER_MAX_REPEATS, "timed frames of each"),
	};
	struct rs_cli cli = {.prog = "raystream-peer-tmb",
	                     .usage = "--scene SCENE (--mesh-out FILE | --bvh DIR) [options]",
	                     .about =
	                         "Primary rays, ours against three-mesh-bvh's GLSL traversal on "
	                         "the same EGL driver;\nrun by tools/peer-three-mesh-bvh.sh "
	                         "(docs/benchmarks.md). Ours: the hits-only kernel, --nodes "
	                         "compact:octant\nunless given.\n",
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .render = &o.render,
	                     .render_keys = "size,nodes"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code;
	if (!o.scene || !o.mesh_out == !o.bvh)
		return rs_cli_usage_error(&cli,
		                          "--scene and one of --mesh-out or --bvh are needed");
	struct rs_error err = {0};
	struct peer_run p = {0};
	enum rs_status st = rs_scenegen_load(o.scene, &p.scene, &err);
	if (st == RS_OK && rs_scene_instance_count(p.scene) > 0)
		st = rs_error_set(&err, RS_ERR_UNSUPPORTED,
		                  "%s is instanced; the peer takes a mesh", o.scene);
	if (st == RS_OK)
		st = o.mesh_out ? write_mesh(p.scene, o.mesh_out, &err) : compare(&o, &p, &err);
	peer_gl_destroy(&p.gl);
	rs_renderer_destroy(&p.ours);
	rs_renderer_destroy(&p.sep);
	rs_renderer_destroy(&p.cpu);
	rs_scene_destroy(&p.scene);
	free(p.cpu_ids);
	free(p.our_ids);
	free(p.sep_ids);
	free(p.their_ids);
	free(p.slots);
	return st == RS_OK ? 0 : rs_cli_fail(&cli, &err);
}
