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
	if (!text || !*text || *text == '-' || *text == '+')
		return 0;
	char *end = NULL;
	errno = 0;
	unsigned long long v = strtoull(text, &end, 10);
	if (errno || *end || v < min || v > max)
		return 0;
	*out = (uint32_t)v;
	return 1;
}

int rs_tool_parse_size(const char *text, uint32_t *out_w, uint32_t *out_h)
{
	if (!text)
		return 0;
	const char *x = strchr(text, 'x');
	if (!x || x == text || (size_t)(x - text) > 10)
		return 0;
	char w[16];
	memcpy(w, text, (size_t)(x - text));
	w[x - text] = '\0';
	return rs_tool_parse_u32(w, 1, RS_IMAGE_MAX_SIDE, out_w) &&
	       rs_tool_parse_u32(x + 1, 1, RS_IMAGE_MAX_SIDE, out_h);
}

static int is_file(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int rs_tool_find_cow(char *out, size_t size)
{
	const char *dirs[] = {getenv("RS_DATA_DIR"), RS_SOURCE_DATA_DIR, RS_INSTALL_DATA_DIR};
	for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; ++i) {
		if (!dirs[i] || !*dirs[i])
			continue;
		int n = snprintf(out, size, "%s/cow.obj", dirs[i]);
		if (n > 0 && (size_t)n < size && is_file(out))
			return 1;
	}
	return 0;
}

enum rs_status rs_tool_load_scene(const char *name, struct rs_scene **out, struct rs_error *err)
{
	struct rs_scenegen_desc gen;
	struct rs_error gen_err = {0};
	if (rs_scenegen_parse(name, &gen, &gen_err) == RS_OK) {
		char cow[4096];
		if (gen.kind == RS_SCENEGEN_COW) {
			if (!rs_tool_find_cow(cow, sizeof cow))
				return rs_error_set(
				    err, RS_ERR_NOT_FOUND,
				    "cow.obj not found (set RS_DATA_DIR to its folder)");
			gen.cow_path = cow;
		}
		return rs_scenegen_build(&gen, out, err);
	}
	if (!is_file(name))
		return rs_error_set(err, RS_ERR_NOT_FOUND,
		                    "scene '%s' is neither box, mirrors, cowN nor an existing file",
		                    name);
	return rs_load_scene(NULL, name, out, err);
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

int rs_tool_parse_reflections(const char *text, enum rs_reflection_mode *mode, uint32_t *bounces)
{
	*bounces = 0;
	if (strcmp(text, "trace") == 0)
		*mode = RS_REFLECT_TRACE;
	else if (strcmp(text, "envmap") == 0)
		*mode = RS_REFLECT_ENVMAP;
	else if (strcmp(text, "interreflect") == 0)
		*mode = RS_REFLECT_INTERREFLECT;
	else if (strncmp(text, "interreflect:", 13) == 0 &&
	         rs_tool_parse_u32(text + 13, 1, RS_RENDER_MAX_BOUNCES, bounces))
		*mode = RS_REFLECT_INTERREFLECT;
	else
		return 0;
	return 1;
}

int rs_tool_parse_nodes(const char *text, struct rs_pack_desc *pack)
{
	const char *colon = strchr(text, ':');
	size_t n = colon ? (size_t)(colon - text) : strlen(text);
	if (n == 7 && strncmp(text, "compact", n) == 0)
		pack->nodes = RS_PACK_NODES_COMPACT;
	else if (n == 5 && strncmp(text, "paper", n) == 0)
		pack->nodes = RS_PACK_NODES_PAPER;
	else
		return 0;
	if (!colon || strcmp(colon + 1, "directional") == 0)
		pack->orders = RS_PACK_ORDERS_DIRECTIONAL;
	else if (strcmp(colon + 1, "single") == 0)
		pack->orders = RS_PACK_ORDERS_SINGLE;
	else
		return 0;
	return 1;
}

const char *rs_tool_nodes_name(const struct rs_pack_desc *pack, char *out, size_t size)
{
	snprintf(out, size, "%s:%s", pack->nodes == RS_PACK_NODES_PAPER ? "paper" : "compact",
	         pack->orders == RS_PACK_ORDERS_SINGLE ? "single" : "directional");
	return out;
}

int rs_tool_parse_storage(const char *text, enum rs_scene_storage *out)
{
	static const char *const names[3] = {"auto", "2d", "buffer"};
	for (int i = 0; i < 3; ++i)
		if (strcmp(text, names[i]) == 0) {
			*out = (enum rs_scene_storage)i;
			return 1;
		}
	return 0;
}

const char *rs_tool_storage_name(enum rs_scene_storage storage)
{
	return storage == RS_SCENE_STORAGE_BUFFER ? "buffer"
	       : storage == RS_SCENE_STORAGE_2D   ? "2d"
	                                          : "auto";
}

const char *rs_tool_reflections_name(const struct rs_render_desc *desc, char *out, size_t size)
{
	if (desc->reflections == RS_REFLECT_INTERREFLECT)
		snprintf(out, size, "interreflect:%u",
		         desc->reflection_bounces ? desc->reflection_bounces : 1u);
	else
		snprintf(out, size, "%s",
		         desc->reflections == RS_REFLECT_ENVMAP ? "envmap" : "trace");
	return out;
}
