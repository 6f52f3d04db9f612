/* Scene names and the entry point of the generator. */
#include <stdio.h>
#include <string.h>

#include "raystream/rs_scenegen.h"
#include "scenegen_internal.h"

enum rs_status rs_scenegen_parse(const char *name, struct rs_scenegen_desc *out,
                                 struct rs_error *err)
{
	unsigned long n = 0;
	const char *p;

	RS_ASSERT(name && out);
	memset(out, 0, sizeof(*out));
	if (strcmp(name, "box") == 0) {
		out->kind = RS_SCENEGEN_BOX;
		return RS_OK;
	}
	if (strcmp(name, "mirrors") == 0) {
		out->kind = RS_SCENEGEN_MIRRORS;
		return RS_OK;
	}
	if (strcmp(name, "animated") == 0) {
		out->kind = RS_SCENEGEN_ANIMATED;
		return RS_OK;
	}
	if (strncmp(name, "cow", 3) != 0 || name[3] < '1' || name[3] > '9')
		goto bad;
	for (p = name + 3; *p != '\0'; p++) {
		if (*p == 'i' && p[1] == '\0') {
			out->instanced = true;
			break;
		}
		if (*p < '0' || *p > '9')
			goto bad;
		n = n * 10 + (unsigned long)(*p - '0');
		if (n > RS_SCENEGEN_MAX_COWS)
			goto bad;
	}
	out->kind = RS_SCENEGEN_COW;
	out->cows = (uint32_t)n;
	return RS_OK;
bad:
	return rs_error_set(
	    err, RS_ERR_INVALID,
	    "unknown scene '%.64s' (expected box, mirrors, animated, cowN or cowNi, "
	    "N = 1..%u)",
	    name, RS_SCENEGEN_MAX_COWS);
}

enum rs_status rs_scenegen_name(const struct rs_scenegen_desc *desc, char *out, size_t size,
                                struct rs_error *err)
{
	int n;

	RS_ASSERT(desc && out);
	if (desc->cows > RS_SCENEGEN_MAX_COWS)
		return rs_error_set(err, RS_ERR_INVALID, "%u cows (at most %u)",
		                    (unsigned)desc->cows, RS_SCENEGEN_MAX_COWS);
	if (desc->kind == RS_SCENEGEN_BOX)
		n = snprintf(out, size, "box");
	else if (desc->kind == RS_SCENEGEN_MIRRORS)
		n = snprintf(out, size, "mirrors");
	else if (desc->kind == RS_SCENEGEN_ANIMATED)
		n = snprintf(out, size, "animated");
	else if (desc->kind == RS_SCENEGEN_COW)
		n = snprintf(out, size, "cow%u%s", desc->cows == 0 ? 1u : (unsigned)desc->cows,
		             desc->instanced ? "i" : "");
	else
		return rs_error_set(err, RS_ERR_INVALID, "unknown scene kind %d", (int)desc->kind);
	if (n < 0 || (size_t)n >= size)
		return rs_error_set(err, RS_ERR_LIMIT, "scene name longer than %zu bytes", size);
	return RS_OK;
}

enum rs_status rs_scenegen_build(const struct rs_scenegen_desc *desc, struct rs_scene **out,
                                 struct rs_error *err)
{
	struct rs_scene *scene = NULL;
	enum rs_status st;

	RS_ASSERT(desc && out);
	*out = NULL;
	if (desc->kind == RS_SCENEGEN_COW && desc->cows > RS_SCENEGEN_MAX_COWS)
		return rs_error_set(err, RS_ERR_INVALID, "cow scene: %u cows (limit %u)",
		                    (unsigned)desc->cows, RS_SCENEGEN_MAX_COWS);
	if (desc->kind != RS_SCENEGEN_COW && desc->kind != RS_SCENEGEN_BOX &&
	    desc->kind != RS_SCENEGEN_MIRRORS && desc->kind != RS_SCENEGEN_ANIMATED)
		return rs_error_set(err, RS_ERR_INVALID, "unknown scene kind %d", (int)desc->kind);
	if (desc->frame > 0 && desc->kind != RS_SCENEGEN_COW && desc->kind != RS_SCENEGEN_ANIMATED)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "scene kind %d does not move (frame %u asked)", (int)desc->kind,
		                    (unsigned)desc->frame);
	uint32_t fps = desc->fps ? desc->fps : RS_SCENEGEN_DEFAULT_FPS;
	st = rs_scene_create(NULL, &scene, err);
	if (st != RS_OK)
		return st;
	if (desc->kind == RS_SCENEGEN_BOX)
		st = sg_build_box(scene, err);
	else if (desc->kind == RS_SCENEGEN_MIRRORS)
		st = sg_build_mirrors(scene, err);
	else if (desc->kind == RS_SCENEGEN_ANIMATED || desc->kind == RS_SCENEGEN_COW) {
		char found[4096];
		const char *cow = desc->cow_path;
		if (!cow &&
		    (st = rs_scenegen_data_path("cow.obj", found, sizeof found, err)) == RS_OK)
			cow = found;
		if (cow && desc->kind == RS_SCENEGEN_ANIMATED)
			st = sg_build_animated(scene, cow, desc->frame, fps, err);
		else if (cow)
			st = sg_build_cows(scene, cow, desc->cows == 0 ? 1 : desc->cows,
			                   desc->frame, fps, desc->instanced, err);
	}
	if (st != RS_OK) {
		rs_scene_destroy(&scene);
		return st;
	}
	*out = scene;
	return RS_OK;
}
