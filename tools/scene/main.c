/*
 * raystream-scene: build a benchmark scene (or load a mesh file) and export it as OBJ + MTL
 * + JSON view file, or print what it contains. Files written are named on stdout.
 */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_load.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_scenegen.h"

static void print_info(const char *name, const struct rs_scene *s)
{
	struct rs_bounds b;
	struct rs_camera c;
	struct rs_environment env;
	const struct rs_light *l = rs_scene_lights(s);

	rs_scene_bounds(s, &b);
	rs_camera_resolve(rs_scene_camera(s), &c);
	rs_scene_environment(s, &env);
	printf("scene: %s\n", name);
	printf("triangles: %zu\nvertices: %zu\nmaterials: %zu\n", rs_scene_triangle_count(s),
	       rs_scene_vertex_count(s), rs_scene_material_count(s));
	printf("bounds: [%.4f %.4f %.4f] .. [%.4f %.4f %.4f]\n", b.lo[0], b.lo[1], b.lo[2], b.hi[0],
	       b.hi[1], b.hi[2]);
	printf("camera: eye [%.4f %.4f %.4f] target [%.4f %.4f %.4f] up [%g %g %g] fov %g "
	       "size %ux%u\n",
	       c.eye[0], c.eye[1], c.eye[2], c.target[0], c.target[1], c.target[2], c.up[0],
	       c.up[1], c.up[2], c.fov_y_deg, (unsigned)c.width, (unsigned)c.height);
	printf("lights: %zu\n", rs_scene_light_count(s));
	for (size_t i = 0; i < rs_scene_light_count(s); i++)
		printf("  L%zu [%.4f %.4f %.4f] colour [%g %g %g]\n", i + 1, l[i].position[0],
		       l[i].position[1], l[i].position[2], l[i].color[0], l[i].color[1],
		       l[i].color[2]);
	printf("environment: centre [%.4f %.4f %.4f] half size %.4f grid %u\n", env.center[0],
	       env.center[1], env.center[2], env.half_size, (unsigned)env.grid);
	printf("ambient: %g\n", rs_scene_ambient(s));
}

/* The MTL rs_scene_export() writes beside `obj`: its name with the extension replaced. */
static void mtl_path(const char *obj, char *out, size_t size)
{
	const char *slash = strrchr(obj, '/'), *dot = strrchr(obj, '.');
	size_t n = dot && (!slash || dot > slash) ? (size_t)(dot - obj) : strlen(obj);
	snprintf(out, size, "%.*s.mtl", (int)n, obj);
}

int main(int argc, char **argv)
{
	const char *scene_name = NULL, *cow = NULL, *out_obj = NULL, *out_view = NULL;
	char view_buf[4096], mtl_buf[4096];
	bool info = false;
	struct rs_scene *scene = NULL;
	struct rs_error err = {0};
	enum rs_status st;
	const struct rs_cli_option opts[] = {
	    RS_CLI_STRING_OPT("--scene", &scene_name, "SCENE",
	                      "box, mirrors, cow1..cow1024, or an OBJ/PLY file (+ its .json)"),
	    {.name = "--cow",
	     .kind = RS_CLI_STRING,
	     .out = &cow,
	     .arg = "COW.obj",
	     .help = "cow model for cowN",
	     .fallback = "the shipped cow.obj"},
	    RS_CLI_STRING_OPT("--out-obj", &out_obj, "F.obj",
	                      "write the scene as OBJ + MTL beside it"),
	    {.name = "--out-view",
	     .kind = RS_CLI_STRING,
	     .out = &out_view,
	     .arg = "F.json",
	     .help = "write camera, lights and environment",
	     .fallback = "F.obj's .json sidecar"},
	    RS_CLI_FLAG_OPT("--info", &info, "print counts, bounds, camera and lights"),
	};
	struct rs_cli cli = {
	    .prog = "raystream-scene",
	    .usage = "--scene SCENE [--out-obj F.obj [--out-view F.json]] [--info]",
	    .about = "The shipped cow.obj is found in $RS_DATA_DIR, else PREFIX/share/raystream\n"
	             "beside the program, else the source tree (docs/scenes.md). Every file\n"
	             "written is named on stdout.\n",
	    .options = opts,
	    .option_count = sizeof opts / sizeof opts[0]};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code;
	if (scene_name == NULL || (!info && out_obj == NULL))
		return rs_cli_usage_error(&cli, "give --scene and --out-obj and/or --info");
	if (out_view != NULL && out_obj == NULL)
		return rs_cli_usage_error(&cli, "--out-view needs --out-obj");
	struct rs_scenegen_desc desc;
	if (cow && rs_scenegen_parse(scene_name, &desc, NULL) == RS_OK) {
		desc.cow_path = cow;
		st = rs_scenegen_build(&desc, &scene, &err);
	} else {
		st = rs_scenegen_load(scene_name, &scene, &err);
	}
	if (st == RS_OK && out_obj != NULL) {
		if (out_view == NULL &&
		    (st = rs_load_sidecar_path(out_obj, view_buf, sizeof(view_buf), &err)) == RS_OK)
			out_view = view_buf;
		if (st == RS_OK)
			st = rs_scene_export(scene, out_obj, out_view, &err);
		if (st == RS_OK) {
			mtl_path(out_obj, mtl_buf, sizeof mtl_buf);
			rs_cli_wrote(out_obj);
			rs_cli_wrote(mtl_buf);
			rs_cli_wrote(out_view);
		}
	}
	if (st == RS_OK && info)
		print_info(scene_name, scene);
	rs_scene_destroy(&scene);
	return st == RS_OK ? 0 : rs_cli_fail(&cli, &err);
}
