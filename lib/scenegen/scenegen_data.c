/* Where the shipped models are: found from the environment, from the install the running
 * program belongs to, or from the source tree it was built in, so no program hard-codes a
 * path and an installed tool works with the source tree gone (docs/scenes.md). */
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "raystream/rs_load.h"
#include "raystream/rs_scenegen.h"

static bool is_file(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* "<dir>/<file>" into out when that is a regular file. */
static bool try_dir(const char *dir, const char *file, char *out, size_t size)
{
	if (!dir || !*dir)
		return false;
	int n = snprintf(out, size, "%s/%s", dir, file);
	return n > 0 && (size_t)n < size && is_file(out);
}

/* PREFIX/share/raystream for a program at PREFIX/bin/NAME (any folder name in place of bin). */
static bool exe_share_dir(char *out, size_t size)
{
	char exe[4096];
	int saved = errno; /* the library leaves errno as it found it */
	ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
	errno = saved;
	if (n <= 0)
		return false;
	exe[n] = '\0';
	for (int up = 0; up < 2; ++up) { /* strip NAME, then bin */
		char *slash = strrchr(exe, '/');
		if (!slash)
			return false;
		*slash = '\0';
	}
	int m = snprintf(out, size, "%s/share/raystream", exe[0] ? exe : "");
	return m > 0 && (size_t)m < size;
}

enum rs_status rs_scenegen_data_path(const char *file, char *out, size_t size, struct rs_error *err)
{
	RS_ASSERT(file && out && size > 0);
	out[0] = '\0';
	const char *env = getenv("RS_DATA_DIR");
	if (env && *env) {
		/* Set, it is the one place: a wrong folder is an error, not a silent fallback
		 * to another copy. */
		if (try_dir(env, file, out, size))
			return RS_OK;
		out[0] = '\0';
		return rs_error_set(err, RS_ERR_NOT_FOUND, "%s not found in RS_DATA_DIR (%s)", file,
		                    env);
	}
	char share[4096];
	if (exe_share_dir(share, sizeof share) && try_dir(share, file, out, size))
		return RS_OK;
	if (try_dir(RS_SOURCE_DATA_DIR, file, out, size) ||
	    try_dir(RS_INSTALL_DATA_DIR, file, out, size))
		return RS_OK;
	out[0] = '\0';
	return rs_error_set(err, RS_ERR_NOT_FOUND,
	                    "%s not found (set RS_DATA_DIR to its folder; looked in "
	                    "PREFIX/share/raystream beside the program, %s and %s)",
	                    file, RS_SOURCE_DATA_DIR, RS_INSTALL_DATA_DIR);
}

enum rs_status rs_scenegen_load(const char *name, struct rs_scene **out, struct rs_error *err)
{
	return rs_scenegen_load_frame(name, 0, 0, out, err);
}

bool rs_scenegen_moves(const char *name)
{
	struct rs_scenegen_desc gen;
	return name && rs_scenegen_parse(name, &gen, NULL) == RS_OK &&
	       (gen.kind == RS_SCENEGEN_ANIMATED || gen.kind == RS_SCENEGEN_COW);
}

enum rs_status rs_scenegen_load_frame(const char *name, uint32_t frame, uint32_t fps,
                                      struct rs_scene **out, struct rs_error *err)
{
	RS_ASSERT(name && out);
	*out = NULL;
	struct rs_scenegen_desc gen;
	if (frame > 0 && !rs_scenegen_moves(name))
		return rs_error_set(
		    err, RS_ERR_INVALID,
		    "scene '%.64s' does not move: frame %u needs 'animated', cowN or cowNi", name,
		    frame);
	if (rs_scenegen_parse(name, &gen, NULL) == RS_OK) {
		gen.frame = frame;
		gen.fps = fps;
		return rs_scenegen_build(&gen, out, err);
	}
	if (!is_file(name))
		return rs_error_set(
		    err, RS_ERR_NOT_FOUND,
		    "scene '%s' is neither box, mirrors, animated, cowN (N 1..%u), cowNi "
		    "nor an existing file",
		    name, RS_SCENEGEN_MAX_COWS);
	return rs_load_scene(NULL, name, out, err);
}
