/* Scene lookup, BVH + packing, strict argument parsing and JSON output for the tools. */
#include "tool_common.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "private/rs_atomic_file.h"

double rs_tool_cpu_ms(void)
{
	struct rusage u;
	getrusage(RUSAGE_SELF, &u);
	return (double)(u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
	       (double)(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-3;
}

int rs_tool_cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

double rs_tool_median(double *v, uint32_t n)
{
	qsort(v, n, sizeof *v, rs_tool_cmp_double);
	return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int rs_tool_parse_u32(const char *text, uint32_t min, uint32_t max, uint32_t *out)
{
	return rs_cli_parse_u32(text, min, max, out);
}

int rs_tool_parse_size(const char *text, uint32_t *out_w, uint32_t *out_h)
{
	return rs_cli_parse_size(text, RS_IMAGE_MAX_SIDE, out_w, out_h);
}

enum rs_status rs_tool_write_text(const char *path, const char *text, struct rs_error *err)
{
	struct rs_atomic_file af;
	enum rs_status status = rs_atomic_open(&af, path, err);
	if (status == RS_OK) {
		/* A failed write sets the stream's error flag, which the commit checks. */
		fputs(text, af.f);
		status = rs_atomic_commit(&af, true, err);
	}
	return status;
}

enum rs_status rs_tool_write_json(const char *path, const cJSON *doc, struct rs_error *err)
{
	char *text = cJSON_Print(doc);
	if (!text)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory formatting %s", path);
	size_t n = strlen(text);
	char *line = malloc(n + 2);
	if (line) {
		memcpy(line, text, n);
		line[n] = '\n';
		line[n + 1] = '\0';
	}
	cJSON_free(text);
	if (!line)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory formatting %s", path);
	enum rs_status status = rs_tool_write_text(path, line, err);
	free(line);
	return status;
}

/* The option parsers below are the library's (rs_render_desc_set/get), kept under their old
 * names until every tool reads its options through rs_cli. */
int rs_tool_parse_reflections(const char *text, enum rs_reflection_mode *mode, uint32_t *bounces)
{
	struct rs_render_desc d = {0};
	if (rs_render_desc_set(&d, "reflections", text, NULL) != RS_OK)
		return 0;
	*mode = d.reflections;
	*bounces = d.reflection_bounces;
	return 1;
}

int rs_tool_parse_nodes(const char *text, struct rs_pack_desc *pack)
{
	struct rs_render_desc d = {.pack = *pack};
	if (rs_render_desc_set(&d, "nodes", text, NULL) != RS_OK)
		return 0;
	*pack = d.pack;
	return 1;
}

const char *rs_tool_nodes_name(const struct rs_pack_desc *pack, char *out, size_t size)
{
	struct rs_render_desc d = {.pack = *pack};
	rs_render_desc_get(&d, "nodes", out, size, NULL);
	return out;
}

int rs_tool_parse_storage(const char *text, enum rs_scene_storage *out)
{
	struct rs_render_desc d = {0};
	if (rs_render_desc_set(&d, "scene-storage", text, NULL) != RS_OK)
		return 0;
	*out = d.scene_storage;
	return 1;
}

const char *rs_tool_storage_name(enum rs_scene_storage storage)
{
	return storage == RS_SCENE_STORAGE_BUFFER ? "buffer"
	       : storage == RS_SCENE_STORAGE_2D   ? "2d"
	                                          : "auto";
}

const char *rs_tool_reflections_name(const struct rs_render_desc *desc, char *out, size_t size)
{
	rs_render_desc_get(desc, "reflections", out, size, NULL);
	return out;
}

const char *rs_tool_shadows_name(enum rs_shadow_mode shadows)
{
	return shadows == RS_SHADOW_MAP ? "map" : shadows == RS_SHADOW_NONE ? "none" : "rays";
}

void rs_tool_long_options(int argc, char **argv, const char *const (*map)[2], size_t count)
{
	for (int i = 1; i < argc; ++i)
		for (size_t k = 0; k < count; ++k)
			if (strcmp(argv[i], map[k][0]) == 0) {
				argv[i] = (char *)map[k][1];
				break;
			}
}
