/* A failed or interrupted write must never leave a half-written file under the real name. */
#include "atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

enum rs_status rs_atomic_open(const char *path, char *tmp_path, size_t tmp_size, FILE **out,
                              struct rs_error *err)
{
	*out = NULL;
	if (!path || !*path)
		return rs_error_set(err, RS_ERR_INVALID, "no output path given");
	/* Renaming over a device or FIFO (say --out /dev/null, run as root) would replace the
	 * node itself with a regular file; only regular files (or nothing) are replaced. */
	struct stat st;
	if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
		return rs_error_set(err, RS_ERR_IO, "cannot write %s: not a regular file", path);
	int n = snprintf(tmp_path, tmp_size, "%s.tmp-XXXXXX", path);
	if (n < 0 || (size_t)n >= tmp_size)
		return rs_error_set(err, RS_ERR_INVALID, "output path is too long: %s", path);
	int fd = mkstemp(tmp_path);
	if (fd < 0)
		return rs_error_set(err, RS_ERR_IO, "cannot create %s: %s", path, strerror(errno));
	/* mkstemp makes the file private; an image is an ordinary output file. */
	(void)fchmod(fd, 0644);
	FILE *f = fdopen(fd, "wb");
	if (!f) {
		close(fd);
		unlink(tmp_path);
		return rs_error_set(err, RS_ERR_IO, "cannot open %s: %s", path, strerror(errno));
	}
	*out = f;
	return RS_OK;
}

enum rs_status rs_atomic_commit(FILE *file, const char *tmp_path, const char *path, int ok,
                                struct rs_error *err)
{
	int write_error = ferror(file);
	int close_error = fclose(file);
	if (!ok || write_error || close_error) {
		unlink(tmp_path);
		if (!ok)
			return err && err->status != RS_OK ? err->status : RS_ERR_IO;
		return rs_error_set(err, RS_ERR_IO, "cannot write %s", path);
	}
	if (rename(tmp_path, path) != 0) {
		int e = errno;
		unlink(tmp_path);
		return rs_error_set(err, RS_ERR_IO, "cannot write %s: %s", path, strerror(e));
	}
	return RS_OK;
}
