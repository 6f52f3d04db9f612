/*
 * Scene export: OBJ (positions, normals, one object per run of same-material triangles),
 * MTL (mapping documented in rs_load.h) and the JSON view file. Each file is written to a
 * temporary file beside its target, flushed to disk and renamed over it, so readers see
 * the old file or the complete new one, never a part.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "raystream/rs_load.h"
#include "raystream/rs_scenegen.h"
#include "private/rs_atomic_file.h"

static void mtl_name(char *out, size_t size, uint32_t id)
{
	snprintf(out, size, "rs_mat%u", (unsigned)id);
}

static void write_mtl(FILE *f, const struct rs_scene *scene)
{
	const struct rs_material *m = rs_scene_materials(scene);

	fprintf(f, "# raystream materials (Pm = mirror reflectance, d = 1 - transmittance)\n");
	for (size_t i = 0; i < rs_scene_material_count(scene); i++) {
		const struct rs_material *x = &m[i];
		int fresnel = (x->flags & RS_MATERIAL_FRESNEL) != 0;
		int illum = x->transmittance > 0.0f ? (fresnel ? 7 : 6)
		            : x->reflectance > 0.0f ? (fresnel ? 5 : 3)
		                                    : 2;
		char name[32];

		mtl_name(name, sizeof(name), (uint32_t)i);
		fprintf(f, "\nnewmtl %s\n", name);
		fprintf(f, "Kd %.9g %.9g %.9g\n", x->diffuse[0], x->diffuse[1], x->diffuse[2]);
		fprintf(f, "Ks %.9g %.9g %.9g\n", x->specular, x->specular, x->specular);
		fprintf(f, "Ns %.9g\n", x->shininess);
		fprintf(f, "Ni %.9g\n", x->ior == 0.0f ? 1.0 : (double)x->ior);
		fprintf(f, "d %.9g\n", 1.0 - (double)x->transmittance);
		fprintf(f, "Pm %.9g\n", x->reflectance);
		fprintf(f, "illum %d\n", illum);
	}
}

static void write_obj(FILE *f, const struct rs_scene *scene, const char *mtl_base)
{
	const float *p = rs_scene_positions(scene), *n = rs_scene_normals(scene);
	const uint32_t *idx = rs_scene_indices(scene), *mat = rs_scene_triangle_materials(scene);
	size_t verts = rs_scene_vertex_count(scene), tris = rs_scene_triangle_count(scene);
	size_t part = 0;

	fprintf(f, "# raystream scene: %zu triangles, %zu vertices\n", tris, verts);
	fprintf(f, "mtllib %s\n", mtl_base);
	for (size_t v = 0; v < verts; v++)
		fprintf(f, "v %.9g %.9g %.9g\n", p[3 * v], p[3 * v + 1], p[3 * v + 2]);
	for (size_t v = 0; v < verts; v++)
		fprintf(f, "vn %.9g %.9g %.9g\n", n[3 * v], n[3 * v + 1], n[3 * v + 2]);
	for (size_t t = 0; t < tris; t++) {
		if (t == 0 || mat[t] != mat[t - 1]) {
			char name[32];

			/* A new object per run keeps assimp's meshes in triangle order. */
			mtl_name(name, sizeof(name), mat[t]);
			fprintf(f, "o part%zu\nusemtl %s\n", part++, name);
		}
		fprintf(f, "f %u//%u %u//%u %u//%u\n", idx[3 * t] + 1, idx[3 * t] + 1,
		        idx[3 * t + 1] + 1, idx[3 * t + 1] + 1, idx[3 * t + 2] + 1,
		        idx[3 * t + 2] + 1);
	}
}

/* obj_path with its extension replaced by ".mtl" (malloc'd), and its base name. */
static char *mtl_path_for(const char *obj_path, const char **out_base)
{
	size_t len = strlen(obj_path) + sizeof(".json");
	char *s = malloc(len);
	const char *slash;

	if (s == NULL || rs_load_sidecar_path(obj_path, s, len, NULL) != RS_OK) {
		free(s);
		return NULL;
	}
	memcpy(s + strlen(s) - 5, ".mtl", 5);
	slash = strrchr(s, '/');
	*out_base = slash != NULL ? slash + 1 : s;
	return s;
}

enum rs_status rs_scene_export(const struct rs_scene *scene, const char *obj_path,
                               const char *view_path, struct rs_error *err)
{
	struct rs_atomic_file o[3] = {{NULL, NULL, NULL}, {NULL, NULL, NULL}, {NULL, NULL, NULL}};
	const char *mtl_base = NULL;
	char *mtl_path, *view = NULL;
	enum rs_status st;

	RS_ASSERT(scene && obj_path);
	if (obj_path[0] == '\0')
		return rs_error_set(err, RS_ERR_INVALID, "export: empty file name");
	if (rs_scene_triangle_count(scene) == 0)
		return rs_error_set(err, RS_ERR_INVALID, "export: the scene has no triangles");
	if (view_path != NULL && (st = rs_load_view_format(scene, &view, err)) != RS_OK)
		return st;
	mtl_path = mtl_path_for(obj_path, &mtl_base);
	if (mtl_path == NULL) {
		rs_free(view);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "export: out of memory");
	}
	/* "scene.mtl" as the OBJ, or the OBJ's own name as the view file, would have one file
	 * silently replace another. */
	if (strcmp(mtl_path, obj_path) == 0 ||
	    (view != NULL &&
	     (strcmp(view_path, obj_path) == 0 || strcmp(view_path, mtl_path) == 0))) {
		rs_free(view);
		free(mtl_path);
		return rs_error_set(err, RS_ERR_INVALID,
		                    "export: %s: the OBJ, MTL and view files need distinct names",
		                    obj_path);
	}
	/* All files are written to temporaries first and renamed only when every one is
	 * complete, so a failure (an unwritable view path, say) leaves no part of the set. */
	const char *paths[3] = {mtl_path, obj_path, view != NULL ? view_path : NULL};
	st = RS_OK;
	for (int i = 0; i < 3 && st == RS_OK; i++) {
		if (paths[i] == NULL)
			continue;
		st = rs_atomic_open(&o[i], paths[i], err);
		if (st != RS_OK)
			break;
		if (i == 0)
			write_mtl(o[i].f, scene);
		else if (i == 1)
			write_obj(o[i].f, scene, mtl_base);
		else if (fputs(view, o[i].f) >= 0)
			fputc('\n', o[i].f);
		st = rs_atomic_finish(&o[i], true, err);
	}
	for (int i = 0; i < 3; i++) {
		enum rs_status c = rs_atomic_commit(&o[i], st == RS_OK, err);
		st = st == RS_OK ? c : st;
	}
	rs_free(view);
	free(mtl_path);
	return st;
}
