/*
 * raystream-scene: build a benchmark scene (or load a mesh file) and export it as OBJ + MTL
 * + JSON view file, or print what it contains.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_load.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_scenegen.h"
#include "tool_common.h"

static void usage(FILE *f)
{
	fprintf(f,
	        "usage: raystream-scene --scene box|cowN|FILE [--cow COW.obj]\n"
	        "                       [--out-obj F.obj [--out-view F.json]] [--info]\n"
	        "  --scene     box, cow1..cow%u, or an OBJ/PLY file (+ its .json sidecar)\n"
	        "  --cow       cow model for cowN (default $RS_DATA_DIR/cow.obj, the\n"
	        "              source tree's data/ or the installed share/raystream/)\n"
	        "  --out-obj   write the scene as OBJ + MTL (beside it, same name)\n"
	        "  --out-view  write the camera/lights file (default: F.obj's .json sidecar)\n"
	        "  --info      print counts, bounds, camera and lights\n",
	        RS_SCENEGEN_MAX_COWS);
}

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

int main(int argc, char **argv)
{
	const char *scene_name = NULL, *cow = NULL, *out_obj = NULL, *out_view = NULL;
	char cow_buf[4096], view_buf[4096];
	int info = 0;
	struct rs_scenegen_desc desc;
	struct rs_scene *scene = NULL;
	struct rs_error err;
	enum rs_status st;

	for (int i = 1; i < argc; i++) {
		const char **slot = NULL;

		if (strcmp(argv[i], "--scene") == 0)
			slot = &scene_name;
		else if (strcmp(argv[i], "--cow") == 0)
			slot = &cow;
		else if (strcmp(argv[i], "--out-obj") == 0)
			slot = &out_obj;
		else if (strcmp(argv[i], "--out-view") == 0)
			slot = &out_view;
		else if (strcmp(argv[i], "--info") == 0)
			info = 1;
		else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
			usage(stdout);
			return 0;
		} else {
			fprintf(stderr, "raystream-scene: unknown option '%s'\n", argv[i]);
			return 2;
		}
		if (slot != NULL) {
			if (i + 1 >= argc) {
				fprintf(stderr, "raystream-scene: %s needs a value\n", argv[i]);
				return 2;
			}
			*slot = argv[++i];
		}
	}
	if (scene_name == NULL || (!info && out_obj == NULL)) {
		fprintf(stderr, "raystream-scene: give --scene and --out-obj and/or --info\n");
		return 2;
	}
	if (out_view != NULL && out_obj == NULL) {
		fprintf(stderr, "raystream-scene: --out-view needs --out-obj\n");
		return 2;
	}
	rs_error_clear(&err);
	if (rs_scenegen_parse(scene_name, &desc, NULL) == RS_OK) {
		if (cow == NULL) {
			if (!rs_tool_find_cow(cow_buf, sizeof(cow_buf))) {
				fprintf(stderr,
				        "raystream-scene: cow.obj not found (use --cow or set "
				        "RS_DATA_DIR to its folder)\n");
				return 1;
			}
			cow = cow_buf;
		}
		desc.cow_path = cow;
		st = rs_scenegen_build(&desc, &scene, &err);
	} else {
		st = rs_load_scene(NULL, scene_name, &scene, &err);
		/* "cow0" is no file either: name both readings, as raystream-render does. */
		if (st == RS_ERR_NOT_FOUND)
			rs_error_set(&err, st,
			             "scene '%s' is neither box, cowN (N = 1..%u) nor an existing "
			             "file",
			             scene_name, RS_SCENEGEN_MAX_COWS);
	}
	if (st != RS_OK) {
		fprintf(stderr, "raystream-scene: %s\n", err.message);
		return 1;
	}
	if (out_obj != NULL) {
		if (out_view == NULL) {
			if (rs_load_sidecar_path(out_obj, view_buf, sizeof(view_buf), NULL) !=
			    RS_OK) {
				fprintf(stderr, "raystream-scene: path too long: %s\n", out_obj);
				rs_scene_destroy(&scene);
				return 1;
			}
			out_view = view_buf;
		}
		st = rs_scene_export(scene, out_obj, out_view, &err);
		if (st != RS_OK) {
			fprintf(stderr, "raystream-scene: %s\n", err.message);
			rs_scene_destroy(&scene);
			return 1;
		}
	}
	if (info)
		print_info(scene_name, scene);
	rs_scene_destroy(&scene);
	return 0;
}
