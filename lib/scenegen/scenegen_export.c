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

struct out_file {
	const char *path;
	char *tmp;
	FILE *f;
};

static enum rs_status out_open(struct out_file *o, const char *path, struct rs_error *err)
{
	size_t len = strlen(path) + sizeof(".tmpXXXXXX");
	int fd;

	o->path = path;
	o->f = NULL;
	o->tmp = malloc(len);
	if (o->tmp == NULL)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory", path);
	snprintf(o->tmp, len, "%s.tmpXXXXXX", path);
	fd = mkstemp(o->tmp);
	if (fd < 0) {
		int e = errno;

		free(o->tmp);
		o->tmp = NULL;
		return rs_error_set(err, RS_ERR_IO, "%s: cannot create: %s", path, strerror(e));
	}
	/* mkstemp makes 0600 files; exported scenes are meant to be shared. */
	(void)fchmod(fd, 0644);
	o->f = fdopen(fd, "w");
	if (o->f == NULL) {
		close(fd);
		unlink(o->tmp);
		free(o->tmp);
		o->tmp = NULL;
		return rs_error_set(err, RS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
	}
	return RS_OK;
}

/* Finish (ok != 0: flush, sync, rename into place) or abandon the file; frees o. */
static enum rs_status out_close(struct out_file *o, int ok, struct rs_error *err)
{
	enum rs_status st = RS_OK;
	int e = 0;

	if (o->f == NULL)
		return RS_OK;
	if (ok && (fflush(o->f) != 0 || ferror(o->f) || fsync(fileno(o->f)) != 0)) {
		e = errno;
		ok = 0;
		st = rs_error_set(err, RS_ERR_IO, "%s: write failed: %s", o->path, strerror(e));
	}
	if (fclose(o->f) != 0 && ok) {
		ok = 0;
		st = rs_error_set(err, RS_ERR_IO, "%s: write failed: %s", o->path, strerror(errno));
	}
	if (ok && rename(o->tmp, o->path) != 0) {
		ok = 0;
		st = rs_error_set(err, RS_ERR_IO, "%s: cannot replace: %s", o->path,
		                  strerror(errno));
	}
	if (!ok)
		unlink(o->tmp);
	free(o->tmp);
	o->tmp = NULL;
	o->f = NULL;
	return st;
}

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

	if (s == NULL || rs_load_sidecar_path(obj_path, s, len) != RS_OK) {
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
	struct out_file o;
	const char *mtl_base = NULL;
	char *mtl_path, *view = NULL;
	enum rs_status st;

	if (scene == NULL || obj_path == NULL || obj_path[0] == '\0')
		return rs_error_set(err, RS_ERR_INVALID, "export: no scene or file name given");
	if (rs_scene_triangle_count(scene) == 0)
		return rs_error_set(err, RS_ERR_INVALID, "export: the scene has no triangles");
	if (view_path != NULL && (st = rs_load_view_format(scene, &view, err)) != RS_OK)
		return st;
	mtl_path = mtl_path_for(obj_path, &mtl_base);
	if (mtl_path == NULL) {
		rs_load_free(view);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "export: out of memory");
	}
	st = out_open(&o, mtl_path, err);
	if (st == RS_OK) {
		write_mtl(o.f, scene);
		st = out_close(&o, 1, err);
	}
	if (st == RS_OK && (st = out_open(&o, obj_path, err)) == RS_OK) {
		write_obj(o.f, scene, mtl_base);
		st = out_close(&o, 1, err);
	}
	if (st == RS_OK && view != NULL && (st = out_open(&o, view_path, err)) == RS_OK) {
		fputs(view, o.f);
		fputc('\n', o.f);
		st = out_close(&o, 1, err);
	}
	rs_load_free(view);
	free(mtl_path);
	return st;
}
