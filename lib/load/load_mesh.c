/*
 * OBJ (+MTL) and PLY meshes through assimp's C API. assimp parses and triangulates; this
 * file checks what it produced (finite numbers, indices in range, some triangles), maps
 * MTL materials onto rs_material and hands the arrays to rs_scene, which copies them.
 * Post-processing is limited to steps that neither drop nor reorder triangles.
 */
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "load_internal.h"
#include "raystream/rs_load.h"

/* rs_scene reads positions/normals straight from assimp's arrays with a stride. */
_Static_assert(sizeof(struct aiVector3D) == 3 * sizeof(float), "assimp built with doubles");

/* Triangulate polygons. No JoinIdenticalVertices: it merges positions up to 1e-5 apart
 * (absolute), moving the vertices of small models; rs_load_weld() shares exactly equal ones
 * instead. No FindDegenerates / ImproveCacheLocality / FindInvalidData: they drop or
 * reorder triangles. */
#define RS_LOAD_AI_FLAGS (aiProcess_Triangulate)

void rs_load_default_material(struct rs_material *out)
{
	memset(out, 0, sizeof(*out));
	out->diffuse[0] = out->diffuse[1] = out->diffuse[2] = 0.8f;
}

static float clamp01(float v)
{
	return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
}

/* MTL -> rs_material; the mapping is documented in rs_load.h and docs/scenes.md. */
static void map_material(const struct aiMaterial *m, struct rs_material *out)
{
	struct aiColor4D c;
	float f;
	int illum = 2;
	int has_pm;

	memset(out, 0, sizeof(*out));
	if (aiGetMaterialColor(m, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS) {
		out->diffuse[0] = c.r;
		out->diffuse[1] = c.g;
		out->diffuse[2] = c.b;
	}
	if (aiGetMaterialColor(m, AI_MATKEY_COLOR_SPECULAR, &c) == aiReturn_SUCCESS)
		out->specular = (c.r + c.g + c.b) / 3.0f;
	if (aiGetMaterialFloatArray(m, AI_MATKEY_SHININESS, &f, NULL) == aiReturn_SUCCESS)
		out->shininess = f;
	if (aiGetMaterialFloatArray(m, AI_MATKEY_REFRACTI, &f, NULL) == aiReturn_SUCCESS)
		out->ior = f;
	if (aiGetMaterialFloatArray(m, AI_MATKEY_OPACITY, &f, NULL) == aiReturn_SUCCESS)
		out->transmittance = clamp01(1.0f - f);
	aiGetMaterialIntegerArray(m, "$mat.illum", 0, 0, &illum, NULL);
	has_pm =
	    aiGetMaterialFloatArray(m, AI_MATKEY_METALLIC_FACTOR, &f, NULL) == aiReturn_SUCCESS;
	if (has_pm)
		out->reflectance = f;
	else if (illum == 3 || illum == 5 || illum == 7)
		out->reflectance = out->specular; /* MTL: ray-traced reflection tinted by Ks */
	if (illum == 5 || illum == 7)
		out->flags |= RS_MATERIAL_FRESNEL;
}

static int is_default_material(const struct aiMaterial *m)
{
	struct aiString name;

	if (aiGetMaterialString(m, AI_MATKEY_NAME, &name) != aiReturn_SUCCESS)
		return 1;
	return strcmp(name.data, AI_DEFAULT_MATERIAL_NAME) == 0;
}

static size_t mesh_triangles(const struct aiMesh *mesh)
{
	size_t n = 0;

	for (unsigned f = 0; f < mesh->mNumFaces; f++)
		n += mesh->mFaces[f].mNumIndices == 3;
	return n;
}

static int finite3(const struct aiVector3D *v)
{
	return isfinite(v->x) && isfinite(v->y) && isfinite(v->z);
}

/*
 * Everything rs_scene would reject, found before the scene is touched. This runs on the raw
 * import, before any post-processing: Triangulate would read through an out-of-range index
 * (PLY), and assimp's JoinIdenticalVertices (not used now) quietly rewrote one.
 */
static enum rs_status check_mesh(const char *path, unsigned index, const struct aiMesh *mesh,
                                 int check_normals, struct rs_error *err)
{
	for (unsigned v = 0; v < mesh->mNumVertices; v++) {
		if (!finite3(&mesh->mVertices[v]))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "%s: mesh %u vertex %u has a non-finite position", path,
			                    index, v);
		if (check_normals && mesh->mNormals != NULL && !finite3(&mesh->mNormals[v]))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "%s: mesh %u vertex %u has a non-finite normal", path,
			                    index, v);
	}
	for (unsigned f = 0; f < mesh->mNumFaces; f++) {
		const struct aiFace *face = &mesh->mFaces[f];

		/* An empty face (a PLY list of length 0, or a misread binary body) makes the
		 * mesh claim polygons it does not have, and assimp's Triangulate step then
		 * aborts the process on an assertion. */
		if (face->mNumIndices == 0)
			return rs_error_set(err, RS_ERR_PARSE,
			                    "%s: mesh %u face %u has no vertices", path, index, f);
		for (unsigned k = 0; k < face->mNumIndices; k++)
			if (face->mIndices[k] >= mesh->mNumVertices)
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "%s: mesh %u face %u: vertex index %u out of "
				                    "range (%u vertices)",
				                    path, index, f, face->mIndices[k],
				                    mesh->mNumVertices);
	}
	return RS_OK;
}

/* assimp's message, cut to its first line (rs_error keeps messages one line). */
static enum rs_status import_error(const char *path, struct rs_error *err)
{
	const char *msg = aiGetErrorString();
	char line[160];
	size_t n = 0;

	if (msg == NULL || msg[0] == '\0')
		msg = "unknown error";
	while (msg[n] != '\0' && msg[n] != '\n' && msg[n] != '\r' && n + 1 < sizeof(line)) {
		line[n] = msg[n];
		n++;
	}
	line[n] = '\0';
	return rs_error_set(err, RS_ERR_PARSE, "%s: cannot import: %s", path, line);
}

/* Material slot of a mesh: its aiMaterial, or mNumMaterials for "none given". */
static unsigned material_slot(const struct aiScene *ai, const struct aiMesh *mesh)
{
	unsigned slot = mesh->mMaterialIndex;

	if (slot >= ai->mNumMaterials || is_default_material(ai->mMaterials[slot]))
		slot = ai->mNumMaterials;
	return slot;
}

static void resolve_material(const struct rs_load_desc *desc, const struct aiScene *ai,
                             unsigned slot, struct rs_material *out)
{
	if (slot < ai->mNumMaterials)
		map_material(ai->mMaterials[slot], out);
	else if (desc->default_material != NULL)
		*out = *desc->default_material;
	else
		rs_load_default_material(out);
}

/* Materials rs_scene would refuse (NaN, negative), found on a scratch scene first. */
static enum rs_status check_materials(const struct rs_load_desc *desc, const char *path,
                                      const struct aiScene *ai, struct rs_error *err)
{
	struct rs_scene *scratch = NULL;
	enum rs_status st = rs_scene_create(NULL, &scratch, err);

	for (unsigned m = 0; st == RS_OK && m < ai->mNumMeshes; m++) {
		struct rs_material mat;
		unsigned slot = material_slot(ai, ai->mMeshes[m]);
		uint32_t id;

		if (mesh_triangles(ai->mMeshes[m]) == 0)
			continue;
		resolve_material(desc, ai, slot, &mat);
		st = rs_scene_add_material(scratch, &mat, &id, err);
		if (st != RS_OK)
			rs_error_prefix(err, st, "%s: bad material", path);
	}
	rs_scene_destroy(&scratch);
	return st;
}

/* Weld the mesh's vertices exactly (rs_load_weld), remap `indices` in place and add it. */
static enum rs_status add_welded(const struct aiMesh *mesh, int use_normals, uint32_t *indices,
                                 size_t tris, uint32_t material, struct rs_scene *scene,
                                 struct rs_error *err)
{
	size_t n = mesh->mNumVertices, unique = 0;
	const float *nrm = use_normals ? &mesh->mNormals[0].x : NULL;
	uint32_t *remap = malloc(n * sizeof(*remap)), *source = malloc(n * sizeof(*source));
	float *pos = malloc(n * 3 * sizeof(*pos)), *nn = malloc(n * 3 * sizeof(*nn));
	enum rs_status st = RS_ERR_NO_MEMORY;

	if (remap != NULL && source != NULL && pos != NULL && nn != NULL)
		st = rs_load_weld(&mesh->mVertices[0].x, nrm, sizeof(struct aiVector3D), n, remap,
		                  source, &unique);
	if (st == RS_OK) {
		struct rs_mesh_desc md;

		for (size_t u = 0; u < unique; u++) {
			memcpy(&pos[3 * u], &mesh->mVertices[source[u]], 3 * sizeof(float));
			if (nrm != NULL)
				memcpy(&nn[3 * u], &mesh->mNormals[source[u]], 3 * sizeof(float));
		}
		for (size_t i = 0; i < tris * 3; i++)
			indices[i] = remap[indices[i]];
		memset(&md, 0, sizeof(md));
		md.positions = pos;
		md.vertex_count = unique;
		md.normals = nrm != NULL ? nn : NULL;
		md.indices = indices;
		md.triangle_count = tris;
		md.material = material;
		st = rs_scene_add_mesh(scene, &md, err);
	} else if (st == RS_ERR_NO_MEMORY) {
		rs_error_set(err, st, "out of memory");
	}
	free(remap);
	free(source);
	free(pos);
	free(nn);
	return st;
}

/* Adds the checked meshes; material ids are created on first use, shared per aiMaterial. */
static enum rs_status add_meshes(const struct rs_load_desc *desc, const char *path,
                                 const struct aiScene *ai, int use_normals, struct rs_scene *scene,
                                 struct rs_error *err)
{
	const uint32_t UNSET = UINT32_MAX;
	uint32_t *ids = malloc(((size_t)ai->mNumMaterials + 1) * sizeof(*ids));
	uint32_t *indices = NULL;
	size_t cap = 0;
	enum rs_status st = RS_OK;

	if (ids == NULL)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory", path);
	for (unsigned i = 0; i <= ai->mNumMaterials; i++)
		ids[i] = UNSET; /* slot mNumMaterials: the default material */
	for (unsigned m = 0; m < ai->mNumMeshes && st == RS_OK; m++) {
		const struct aiMesh *mesh = ai->mMeshes[m];
		size_t tris = mesh_triangles(mesh), t = 0;
		unsigned slot;

		if (tris == 0)
			continue;
		slot = material_slot(ai, mesh);
		if (ids[slot] == UNSET) {
			struct rs_material mat;

			resolve_material(desc, ai, slot, &mat);
			st = rs_scene_add_material(scene, &mat, &ids[slot], err);
			if (st != RS_OK) {
				rs_error_prefix(err, st, "%s: material %u", path, slot);
				break;
			}
		}
		if (tris * 3 > cap) {
			uint32_t *grown = realloc(indices, tris * 3 * sizeof(*indices));

			if (grown == NULL) {
				st = rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory", path);
				break;
			}
			indices = grown;
			cap = tris * 3;
		}
		for (unsigned f = 0; f < mesh->mNumFaces; f++) {
			const struct aiFace *face = &mesh->mFaces[f];

			if (face->mNumIndices != 3)
				continue;
			memcpy(&indices[t * 3], face->mIndices, 3 * sizeof(*indices));
			t++;
		}
		st = add_welded(mesh, use_normals, indices, tris, ids[slot], scene, err);
		if (st != RS_OK)
			rs_error_prefix(err, st, "%s: mesh %u", path, m);
	}
	free(indices);
	free(ids);
	return st;
}

enum rs_status rs_load_mesh_file(const struct rs_load_desc *desc, const char *path,
                                 struct rs_scene *scene, struct rs_error *err)
{
	static const struct rs_load_desc defaults;
	const struct aiScene *ai;
	enum rs_status st;
	size_t total = 0, file_size = 0;
	int use_normals = 1;

	if (desc == NULL)
		desc = &defaults;
	RS_ASSERT(scene && path);
	bool done = false;
	st = rs_load_check_file(path, desc->max_file_bytes, &file_size, err);
	if (st == RS_OK)
		st = rs_load_ply_front(desc, path, file_size, scene, &done, err);
	if (st == RS_OK && !done)
		st = rs_obj_check_body(path, err);
	if (st != RS_OK || done)
		return st;
	ai = aiImportFile(path, 0);
	if (ai == NULL)
		return import_error(path, err);
	for (unsigned m = 0; m < ai->mNumMeshes && st == RS_OK; m++)
		st = check_mesh(path, m, ai->mMeshes[m], !desc->ignore_file_normals, err);
	if (st != RS_OK) {
		aiReleaseImport(ai);
		return st;
	}
	/* On failure assimp has already released the scene. */
	ai = aiApplyPostProcessing(ai, RS_LOAD_AI_FLAGS);
	if (ai == NULL)
		return import_error(path, err);
	for (unsigned m = 0; m < ai->mNumMeshes; m++) {
		const struct aiMesh *mesh = ai->mMeshes[m];

		if (mesh_triangles(mesh) == 0)
			continue;
		/* One mesh without normals means computing them for all: never mix sources. */
		if (desc->ignore_file_normals || mesh->mNormals == NULL)
			use_normals = 0;
		total += mesh_triangles(mesh);
	}
	if (total == 0)
		st = rs_error_set(err, RS_ERR_BAD_DATA, "%s: no triangles", path);
	else if ((st = check_materials(desc, path, ai, err)) == RS_OK)
		st = add_meshes(desc, path, ai, use_normals, scene, err);
	aiReleaseImport(ai);
	return st;
}
