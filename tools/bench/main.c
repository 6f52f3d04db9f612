/*
 * raystream-bench: the paper's tables for this project.
 *   --table 1 (default): hit numbers per scene and builder beside the paper's Table 1, the
 *             triangle tests' speed against error, and BVH build times (table1.c).
 *   --table 2: the paper's Table 2 on a render backend (fps, hit numbers, Mrays/s, time per
 *             kernel for tree BVH 1 pass, raster + BVH 1 and 2 passes) beside the Embree
 *             peer on the same rays when it was built (table2.c, embree/).
 *   --table 3: BVH build time, ours against Embree's medium build on the same threads
 *             (table3.c, embree/embree_build.c).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"
#include "raystream/rs_renderers.h"
#include "tool_common.h"

const char *const bench_scenes[BENCH_SCENE_COUNT] = {"box",  "cow1", "cow2",
                                                     "cow5", "cow9", "cow17"};

void bench_min_max(const double *v, uint32_t n, double *out_min, double *out_max)
{
	*out_min = *out_max = v[0];
	for (uint32_t i = 1; i < n; ++i) {
		*out_min = v[i] < *out_min ? v[i] : *out_min;
		*out_max = v[i] > *out_max ? v[i] : *out_max;
	}
}

static void usage(void)
{
	puts("usage: raystream-bench [--table 1|2|3] [--size N] [--lights N] [--repeats N]\n"
	     "                       [--threads N] [--scene NAME]\n"
	     "  table 1: [--flat-size N] [--passes N] [--none-max-triangles N]\n"
	     "  table 2: [--backend cpu|egl|osmesa] [--bvh none|linear|paper|sah]\n"
	     "           [--peer embree|none] [--scene-storage auto|2d|buffer]\n"
	     "  both:    [--nodes compact|paper[:directional|single]] (table 1: paper:single,\n"
	     "           the paper's layout; table 2: compact:directional)\n"
	     "Scenes: box, cow1, cow2, cow5, cow9, cow17 (default all).");
}

static int bad(const char *what, const char *value)
{
	fprintf(stderr, "raystream-bench: %s%s%s\n", what, value ? " " : "", value ? value : "");
	return 2;
}

static int parse_builder(const char *v, enum rs_bvh_builder *out)
{
	static const char *const names[] = {"none", "linear", "paper", "sah"};
	static const enum rs_bvh_builder ids[] = {RS_BVH_NONE, RS_BVH_LINEAR, RS_BVH_PAPER,
	                                          RS_BVH_SAH};
	for (int i = 0; i < 4; ++i)
		if (!strcmp(v, names[i])) {
			*out = ids[i];
			return 1;
		}
	return 0;
}

static int parse(int argc, char **argv, struct bench_options *o)
{
	*o = (struct bench_options){.table = 1,
	                            .size = 512,
	                            .flat_size = 64,
	                            .none_max_tris = 30000,
	                            .passes = 2,
	                            .lights = 1,
	                            .repeats = 5,
	                            .backend = "cpu",
	                            .builder = RS_BVH_SAH,
	                            .peer = true};
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!strcmp(a, "--help")) {
			usage();
			exit(0);
		}
		uint32_t *dst = !strcmp(a, "--size")                 ? &o->size
		                : !strcmp(a, "--flat-size")          ? &o->flat_size
		                : !strcmp(a, "--passes")             ? &o->passes
		                : !strcmp(a, "--lights")             ? &o->lights
		                : !strcmp(a, "--repeats")            ? &o->repeats
		                : !strcmp(a, "--threads")            ? &o->threads
		                : !strcmp(a, "--none-max-triangles") ? &o->none_max_tris
		                : !strcmp(a, "--table")              ? &o->table
		                                                     : NULL;
		int known = dst || !strcmp(a, "--scene") || !strcmp(a, "--backend") ||
		            !strcmp(a, "--bvh") || !strcmp(a, "--peer") || !strcmp(a, "--nodes") ||
		            !strcmp(a, "--scene-storage");
		if (!known)
			return bad("unknown option:", a);
		if (!v)
			return bad("missing value for", a);
		++i;
		if (!strcmp(a, "--scene")) {
			o->only = v;
		} else if (!strcmp(a, "--backend")) {
			if (!rs_renderer_has_backend(v)) {
				fprintf(
				    stderr,
				    "raystream-bench: unknown backend '%s' (this build has: %s)\n",
				    v, rs_renderer_backends());
				return 2;
			}
			o->backend = v;
		} else if (!strcmp(a, "--bvh")) {
			if (!parse_builder(v, &o->builder))
				return bad("unknown BVH builder (none, linear, paper or sah):", v);
		} else if (!strcmp(a, "--nodes")) {
			if (!rs_tool_parse_nodes(v, &o->pack))
				return bad("--nodes wants compact|paper[:directional|single], not",
				           v);
			o->pack_set = true;
		} else if (!strcmp(a, "--scene-storage")) {
			if (!rs_tool_parse_storage(v, &o->storage))
				return bad("--scene-storage wants auto, 2d or buffer, not", v);
		} else if (!strcmp(a, "--peer")) {
			if (strcmp(v, "embree") != 0 && strcmp(v, "none") != 0)
				return bad("--peer wants embree or none, not", v);
			o->peer = !strcmp(v, "embree");
		} else {
			uint32_t max = dst == &o->repeats         ? 32
			               : dst == &o->table         ? 3
			               : dst == &o->none_max_tris ? 1u << 24
			               : dst == &o->lights        ? 64
			                                          : 16384;
			if (!rs_tool_parse_u32(v, 1, max, dst)) {
				fprintf(stderr, "raystream-bench: bad option %s %s\n", a, v);
				return 2;
			}
		}
	}
	if (o->only) {
		size_t s = 0;
		while (s < BENCH_SCENE_COUNT && strcmp(o->only, bench_scenes[s]) != 0)
			++s;
		/* An unknown name would otherwise print an empty table and exit 0. */
		if (s == BENCH_SCENE_COUNT) {
			fprintf(stderr,
			        "raystream-bench: unknown scene '%s' (box, cow1, cow2, cow5, "
			        "cow9 or cow17)\n",
			        o->only);
			return 2;
		}
	}
	if (!o->threads) {
		long n = sysconf(_SC_NPROCESSORS_ONLN);
		o->threads = n > 0 && n <= 256 ? (uint32_t)n : 1u;
	}
	return 0;
}

int main(int argc, char **argv)
{
	struct bench_options o;
	int code = parse(argc, argv, &o);
	if (code)
		return code;
	if (o.table == 3)
		return bench_table3(&o);
	return o.table == 2 ? bench_table2(&o) : bench_table1(&o);
}
