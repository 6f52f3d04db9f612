/* File checks for the loader: existence, type and size before a parser sees the file. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "load_internal.h"
#include "raystream/rs_load.h"

enum rs_status rs_load_check_file(const char *path, size_t max_bytes, size_t *out_size,
                                  struct rs_error *err)
{
	struct stat st;

	RS_ASSERT(path);
	if (path[0] == '\0')
		return rs_error_set(err, RS_ERR_INVALID, "no file name given");
	if (max_bytes == 0)
		max_bytes = RS_LOAD_DEFAULT_MAX_FILE_BYTES;
	if (stat(path, &st) != 0) {
		int e = errno;
		return rs_error_set(err, e == ENOENT || e == ENOTDIR ? RS_ERR_NOT_FOUND : RS_ERR_IO,
		                    "%s: %s", path, strerror(e));
	}
	if (!S_ISREG(st.st_mode))
		return rs_error_set(err, RS_ERR_IO, "%s: not a regular file", path);
	if (st.st_size < 0 || (unsigned long long)st.st_size > (unsigned long long)max_bytes)
		return rs_error_set(err, RS_ERR_LIMIT, "%s: file too large (%lld bytes, limit %zu)",
		                    path, (long long)st.st_size, max_bytes);
	if (out_size != NULL)
		*out_size = (size_t)st.st_size;
	return RS_OK;
}

enum rs_status rs_load_read_text(const char *path, size_t max_bytes, char **out_text,
                                 size_t *out_size, struct rs_error *err)
{
	size_t size = 0;
	enum rs_status st = rs_load_check_file(path, max_bytes, &size, err);
	FILE *f;
	char *text;
	size_t got;

	*out_text = NULL;
	if (st != RS_OK)
		return st;
	f = fopen(path, "rb");
	if (f == NULL)
		return rs_error_set(err, RS_ERR_IO, "%s: %s", path, strerror(errno));
	text = malloc(size + 1);
	if (text == NULL) {
		fclose(f);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "%s: out of memory (%zu bytes)", path,
		                    size);
	}
	got = fread(text, 1, size, f);
	/* A file that changed size under us is read as far as it goes; the parser judges it. */
	if (ferror(f)) {
		fclose(f);
		free(text);
		return rs_error_set(err, RS_ERR_IO, "%s: read error", path);
	}
	fclose(f);
	text[got] = '\0';
	*out_text = text;
	if (out_size != NULL)
		*out_size = got;
	return RS_OK;
}

enum rs_status rs_load_sidecar_path(const char *path, char *out, size_t size, struct rs_error *err)
{
	RS_ASSERT(path && out);
	const char *slash = strrchr(path, '/');
	const char *base = slash != NULL ? slash + 1 : path;
	const char *dot = strrchr(base, '.');
	/* A leading dot (".hidden") is a name, not an extension. */
	size_t stem = (dot != NULL && dot != base) ? (size_t)(dot - path) : strlen(path);

	if (size == 0 || stem + sizeof(".json") > size)
		return rs_error_set(err, RS_ERR_LIMIT, "%.64s: sidecar path longer than %zu bytes",
		                    path, size);
	memcpy(out, path, stem);
	memcpy(out + stem, ".json", sizeof(".json"));
	return RS_OK;
}

enum rs_status rs_load_map_file(const char *path, const unsigned char **out_bytes, size_t *out_size,
                                struct rs_error *err)
{
	*out_bytes = NULL;
	*out_size = 0;
	int fd = open(path, O_RDONLY);
	struct stat st;
	if (fd < 0 || fstat(fd, &st) != 0) {
		int e = errno;
		if (fd >= 0)
			close(fd);
		return rs_error_set(err, RS_ERR_IO, "%s: %s", path, strerror(e));
	}
	size_t size = (size_t)st.st_size;
	if (size == 0) {
		close(fd);
		return RS_OK;
	}
	void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
	close(fd);
	if (map == MAP_FAILED)
		return rs_error_set(err, RS_ERR_IO, "%s: cannot map %zu bytes", path, size);
	*out_bytes = map;
	*out_size = size;
	return RS_OK;
}

void rs_load_unmap_file(const unsigned char *bytes, size_t size)
{
	if (bytes)
		munmap((void *)bytes, size);
}
