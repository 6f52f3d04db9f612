/* Scene lookup, BVH + packing, strict argument parsing and JSON output for the tools. */
#include "tool_common.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "private/rs_atomic_file.h"

double rs_tool_now_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
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
		                    "scene '%s' is neither box, cowN nor an existing file", name);
	return rs_load_scene(NULL, name, out, err);
}

enum rs_status rs_tool_write_json(const char *path, const cJSON *doc, struct rs_error *err)
{
	char *text = cJSON_Print(doc);
	if (!text)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory formatting %s", path);
	struct rs_atomic_file af;
	enum rs_status status = rs_atomic_open(&af, path, err);
	if (status == RS_OK) {
		/* A failed write sets the stream's error flag, which the commit checks. */
		fputs(text, af.f);
		fputc('\n', af.f);
		status = rs_atomic_commit(&af, true, err);
	}
	cJSON_free(text);
	return status;
}
