/*
 * Fixture files for the loader and scene generator tests: a private temporary directory
 * per test, small files written into it, everything removed afterwards. Include after
 * defining _POSIX_C_SOURCE 200809L.
 */
#ifndef TEST_LOAD_FIXTURE_H
#define TEST_LOAD_FIXTURE_H

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

struct fx {
	char dir[512];
	char path[1024]; /* last path made by fx_path()/fx_write() */
};

static inline void fx_init(struct fx *fx)
{
	const char *tmp = getenv("TMPDIR");

	snprintf(fx->dir, sizeof(fx->dir), "%s/rs_test_XXXXXX",
	         tmp != NULL && tmp[0] != '\0' ? tmp : "/tmp");
	assert_non_null(mkdtemp(fx->dir));
}

static inline const char *fx_path(struct fx *fx, const char *name)
{
	snprintf(fx->path, sizeof(fx->path), "%s/%s", fx->dir, name);
	return fx->path;
}

/* Write `size` bytes (strlen(data) when size is 0) to dir/name; returns the path. */
static inline const char *fx_write_n(struct fx *fx, const char *name, const void *data, size_t size)
{
	FILE *f = fopen(fx_path(fx, name), "wb");

	assert_non_null(f);
	assert_int_equal(fwrite(data, 1, size, f), size);
	assert_int_equal(fclose(f), 0);
	return fx->path;
}

static inline const char *fx_write(struct fx *fx, const char *name, const char *text)
{
	return fx_write_n(fx, name, text, strlen(text));
}

/* Number of entries in the directory (excluding . and ..). */
static inline int fx_count(const struct fx *fx)
{
	DIR *d = opendir(fx->dir);
	struct dirent *e;
	int n = 0;

	assert_non_null(d);
	while ((e = readdir(d)) != NULL)
		n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
	closedir(d);
	return n;
}

static inline void fx_cleanup(struct fx *fx)
{
	DIR *d = opendir(fx->dir);
	struct dirent *e;
	char p[1024];

	if (d == NULL)
		return;
	while ((e = readdir(d)) != NULL) {
		if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
			continue;
		snprintf(p, sizeof(p), "%s/%s", fx->dir, e->d_name);
		rmdir(p); /* test subdirectories are empty */
		unlink(p);
	}
	closedir(d);
	rmdir(fx->dir);
}

/* cmocka's assert_float_equal compares in single precision: this one uses doubles and an
 * absolute tolerance. */
static inline void rs_assert_near(double a, double b, double tol, const char *file, int line)
{
	if (!(fabs(a - b) <= tol)) {
		print_error("%.17g != %.17g (tolerance %g)\n", a, b, tol);
		_fail(file, line);
	}
}
#define assert_near(a, b, tol) rs_assert_near((a), (b), (tol), __FILE__, __LINE__)

/* A status message must be one non-empty line. */
static inline void assert_one_line(const struct rs_error *err)
{
	assert_true(err->message[0] != '\0');
	assert_null(strchr(err->message, '\n'));
}

#endif
