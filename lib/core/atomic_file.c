/* Write-then-rename: see private/rs_atomic_file.h. */
#include "private/rs_atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void release(struct rs_atomic_file *af)
{
	free(af->path);
	free(af->tmp);
	af->path = af->tmp = NULL;
	af->f = NULL;
}

enum rs_status rs_atomic_open(struct rs_atomic_file *af, const char *path, struct rs_error *err)
{
	RS_ASSERT(af && path);
	memset(af, 0, sizeof *af);
	if (!path[0])
		return rs_error_set(err, RS_ERR_INVALID, "no output path given");
	struct stat st;
	if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
		return rs_error_set(err, RS_ERR_IO, "cannot write %s: not a regular file", path);
	size_t n = strlen(path);
	af->path = malloc(n + 1);
	af->tmp = malloc(n + sizeof ".tmp-XXXXXX");
	if (!af->path || !af->tmp) {
		release(af);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory writing %s", path);
	}
	memcpy(af->path, path, n + 1);
	memcpy(af->tmp, path, n);
	memcpy(af->tmp + n, ".tmp-XXXXXX", sizeof ".tmp-XXXXXX");
	int fd = mkstemp(af->tmp);
	if (fd < 0) {
		int e = errno;
		release(af);
		return rs_error_set(err, RS_ERR_IO, "cannot create %s: %s", path, strerror(e));
	}
	/* mkstemp makes the file private; outputs are ordinary files meant to be shared. */
	(void)fchmod(fd, 0644);
	af->f = fdopen(fd, "wb");
	if (!af->f) {
		int e = errno;
		close(fd);
		unlink(af->tmp);
		release(af);
		return rs_error_set(err, RS_ERR_IO, "cannot open %s: %s", path, strerror(e));
	}
	return RS_OK;
}

enum rs_status rs_atomic_finish(struct rs_atomic_file *af, bool ok, struct rs_error *err)
{
	RS_ASSERT(af);
	if (!af->f)
		return RS_OK;
	enum rs_status st = RS_OK;
	if (ok && (fflush(af->f) != 0 || ferror(af->f) || fsync(fileno(af->f)) != 0)) {
		ok = false;
		st = rs_error_set(err, RS_ERR_IO, "cannot write %s: %s", af->path, strerror(errno));
	}
	if (fclose(af->f) != 0 && ok) {
		ok = false;
		st = rs_error_set(err, RS_ERR_IO, "cannot write %s: %s", af->path, strerror(errno));
	}
	af->f = NULL;
	if (!ok) {
		unlink(af->tmp);
		free(af->tmp);
		af->tmp = NULL;
	}
	return st;
}

enum rs_status rs_atomic_commit(struct rs_atomic_file *af, bool ok, struct rs_error *err)
{
	RS_ASSERT(af);
	enum rs_status st = rs_atomic_finish(af, ok, err);
	if (st == RS_OK && !ok)
		st = err && err->status < 0 ? err->status : RS_ERR_IO;
	if (st == RS_OK && af->tmp && rename(af->tmp, af->path) != 0) {
		st = rs_error_set(err, RS_ERR_IO, "cannot write %s: %s", af->path, strerror(errno));
		unlink(af->tmp);
	} else if (st != RS_OK && af->tmp) {
		unlink(af->tmp);
	}
	release(af);
	return st;
}
