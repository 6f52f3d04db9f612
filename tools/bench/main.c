/*
 * raystream-bench: the paper's tables for this project, and frame times per setting.
 *   --table 1 (default): hit numbers per scene and builder beside the paper's Table 1, the
 *             triangle tests' speed against error, and BVH build times (table1.c).
 *   --table 2: the paper's Table 2 on a render backend (fps, hit numbers, Mrays/s, time per
 *             kernel for tree BVH 1 pass, raster + BVH 1 and 2 passes) beside the Embree
 *             peer on the same rays when it was built (table2.c, embree/).
 *   --times SCENE...: frame times of one render setting per scene (times.c; this was
 *             raystream-glbench).
 *   --builds: BVH build time, ours against Embree's medium build on the same threads
 *             (builds.c, embree/embree_build.c).
 *   --animate N SCENE...: per-frame vertex update (refit, repack, partial upload) against a
 *             full set_scene, frames 1..N of scenes that move (animate.c).
 *   --instance-updates [COUNT...]: per-frame cost of moving every one of COUNT instances
 *             (17, 1000, 10000): TLAS build and pack, the renderer's update, set_scene
 *             (instances.c).
 * --json FILE writes the figures beside the tables; progress goes to stderr once a run
 * has taken 2 s.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"
#include "raystream/rs_cli.h"
#include "raystream/rs_renderers.h"
#include "tool_common.h"

const char *const bench_scenes[BENCH_SCENE_COUNT] = {"box",  "cow1", "cow2",
                                                     "cow5", "cow9", "cow17"};

static const char about[] =
    "Table 1 renders on the CPU reference (it counts); Table 2 and --times on --backend,\n"
    "by default the GPU where a GL context opens (auto; a line on stderr says when it falls\n"
    "back to cpu, which traces primary rays only: Table 2's raster rows are then left out\n"
    "and named once). Scenes: box, cow1, cow2, cow5, cow9, cow17 (Tables: default all);\n"
    "--times takes any scene raystream-render does. Table 1 counts the paper's node\n"
    "layout (paper:single) unless --nodes is given. Render options: docs/render.md;\n"
    "figures and commands: docs/benchmarks.md.\n";

static enum rs_status parse_peer(void *out, const char *v, struct rs_error *err)
{
	if (strcmp(v, "embree") != 0 && strcmp(v, "none") != 0)
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not embree|none", v);
	*(bool *)out = !strcmp(v, "embree");
	return RS_OK;
}

static enum rs_status parse_scene(void *out, const char *v, struct rs_error *err)
{
	for (size_t s = 0; s < BENCH_SCENE_COUNT; ++s)
		if (!strcmp(v, bench_scenes[s])) {
			*(const char **)out = bench_scenes[s];
			return RS_OK;
		}
	return rs_error_set(err, RS_ERR_INVALID,
	                    "unknown scene '%s' (box, cow1, cow2, cow5, cow9 or cow17)", v);
}

/* Returns 0 to run, else the exit status (0 after --help, 2 for a usage error). */
static int parse(int argc, char **argv, struct bench_options *o, const char **json_path)
{
	*o = (struct bench_options){.table = 1,
	                            .size = 512,
	                            .flat_size = 64,
	                            .none_max_tris = 30000,
	                            .lights = 1,
	                            .repeats = 5,
	                            .peer = true};
	*json_path = NULL;
	const struct rs_cli_option opts[] = {
	    {.name = "--table",
	     .kind = RS_CLI_U32,
	     .out = &o->table,
	     .arg = "1|2",
	     .help = "the paper's Table 1 (hit numbers) or 2 (frame rates)",
	     .min = 1,
	     .max = 2},
	    RS_CLI_FLAG_OPT("--times", &o->times,
	                    "frame times of the render options per SCENE (was raystream-glbench)"),
	    RS_CLI_FLAG_OPT("--error", &o->error,
	                    "--times: the first frame's error against the CPU reference tracer "
	                    "(traced primaries and reflections, exact feelers; as table 2)"),
	    RS_CLI_FLAG_OPT("--builds", &o->builds,
	                    "BVH build time against Embree's medium build, same threads"),
	    RS_CLI_U32_OPT(
	        "--animate", &o->animate, 1, 240,
	        "frames of each SCENE (animated, cowN, cowNi): update against set_scene"),
	    RS_CLI_FLAG_OPT("--instance-updates", &o->instance_updates,
	                    "moving every one of COUNT... instances [17 1000 10000] a frame: TLAS "
	                    "update, renderer update, set_scene (--repeats frames)"),
	    RS_CLI_CALL_OPT("--scene", &o->only, parse_scene, "NAME",
	                    "tables: one of the paper's scenes [all]"),
	    RS_CLI_U32_OPT("--size", &o->size, 8, 16384, "image side, pixels"),
	    RS_CLI_U32_OPT("--lights", &o->lights, 1, 64, "the scene's first N lights"),
	    RS_CLI_U32_OPT("--repeats", &o->repeats, 1, 32, "timed frames (BVH builds) per row"),
	    RS_CLI_U32_OPT("--flat-size", &o->flat_size, 8, 16384,
	                   "table 1: image side for the none/linear builders"),
	    RS_CLI_U32_OPT("--none-max-triangles", &o->none_max_tris, 1, 16777216,
	                   "table 1: skip builder none above this"),
	    {.name = "--peer",
	     .kind = RS_CLI_CALL,
	     .out = &o->peer,
	     .call = parse_peer,
	     .arg = "embree|none",
	     .help = "table 2: the Intel Embree 3 peer, when built",
	     .fallback = "embree"},
	    RS_CLI_STRING_OPT("--json", json_path, "FILE", "the figures as JSON too"),
	};
	static const char *positional[BENCH_MAX_SCENES];
	struct rs_cli cli = {
	    .prog = "raystream-bench",
	    .usage =
	        "[--table 1|2] [options]  |  --builds [options]  |  --times [options] SCENE...  |  "
	        "--animate N [options] SCENE...  |  --instance-updates [options] [COUNT...]",
	    .about = about,
	    .options = opts,
	    .option_count = sizeof opts / sizeof opts[0],
	    .render = &o->render,
	    .render_keys = "backend,passes,threads,bvh,nodes,scene-storage,"
	                   "primary,shadows,reflections,envmap-size,chain,kernels,triangle-test,"
	                   "instances",
	    .positional = positional,
	    .positional_max = BENCH_MAX_SCENES,
	    .positional_name = "SCENE..."};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code ? code : -1;
	for (int i = 1; i < argc; ++i)
		o->pack_set |= !strncmp(argv[i], "--nodes", 7);
	if (o->times && !cli.positional_count)
		return rs_cli_usage_error(&cli, "--times needs at least one SCENE");
	if (o->error && !o->times)
		return rs_cli_usage_error(&cli, "--error goes with --times");
	if (o->animate && !cli.positional_count)
		return rs_cli_usage_error(&cli, "--animate needs at least one SCENE");
	if ((o->times != 0) + (o->animate != 0) + (o->instance_updates != 0) > 1)
		return rs_cli_usage_error(
		    &cli, "--times, --animate and --instance-updates are separate runs");
	if (!o->times && !o->animate && !o->instance_updates && cli.positional_count)
		return rs_cli_usage_error(&cli, "unexpected argument '%s' (scenes go with --times)",
		                          positional[0]);
	for (size_t i = 0; o->instance_updates && i < cli.positional_count; ++i) {
		uint32_t n;
		if (!rs_tool_parse_u32(positional[i], 1, BENCH_MAX_INSTANCES, &n))
			return rs_cli_usage_error(
			    &cli, "--instance-updates: '%s' is not an instance count 1..%u",
			    positional[i], BENCH_MAX_INSTANCES);
	}
	memcpy(o->scenes, positional, cli.positional_count * sizeof *positional);
	o->scene_count = cli.positional_count;
	const char *b = o->render.backend ? o->render.backend : "auto";
	if (!rs_renderer_has_backend(b))
		return rs_cli_usage_error(&cli,
		                          "--backend: '%s' is not part of this build (have: %s)", b,
		                          rs_renderer_backends());
	o->passes = o->render.passes ? o->render.passes : 2;
	o->builder = o->render.bvh.builder;
	o->pack = o->render.pack;
	o->storage = o->render.scene_storage;
	o->kernels = o->render.kernels;
	o->threads = o->render.threads;
	if (!o->threads) {
		long n = sysconf(_SC_NPROCESSORS_ONLN);
		o->threads = n > 0 && n <= 256 ? (uint32_t)n : 1u;
	}
	/* Table 1 renders on the CPU reference: it needs no backend opened. */
	struct rs_error err = {0};
	if ((o->times || o->animate || o->instance_updates || o->table == 2) &&
	    !(o->backend = rs_tool_backend_name(&cli, &o->render, &err)))
		return rs_cli_fail(&cli, &err);
	return 0;
}

int main(int argc, char **argv)
{
	struct bench_options o;
	const char *json_path;
	int code = parse(argc, argv, &o, &json_path);
	if (code)
		return code < 0 ? 0 : code;
	const struct rs_cli cli = {.prog = "raystream-bench"};
	struct rs_error err = {0};
	/* The JSON target is checked before minutes of work, not after. */
	if (json_path && rs_cli_check_output(json_path, &err) != RS_OK)
		return rs_cli_fail(&cli, &err);
	if (json_path) {
		o.json = cJSON_CreateObject();
		cJSON_AddStringToObject(o.json, "mode",
		                        o.animate            ? "animate"
		                        : o.instance_updates ? "instance-updates"
		                        : o.times            ? "times"
		                        : o.builds           ? "builds"
		                        : o.table == 2       ? "table2"
		                                             : "table1");
		cJSON_AddArrayToObject(o.json, "rows");
	}
	code = o.animate            ? bench_animate(&o)
	       : o.instance_updates ? bench_instance_updates(&o)
	       : o.times            ? bench_times(&o)
	       : o.builds           ? bench_builds(&o)
	       : o.table == 2       ? bench_table2(&o)
	                            : bench_table1(&o);
	if (o.json && code == 0) {
		if (rs_tool_write_json(json_path, o.json, &err) != RS_OK)
			code = rs_cli_fail(&cli, &err);
		else
			rs_cli_wrote(json_path);
	}
	cJSON_Delete(o.json);
	return code;
}
