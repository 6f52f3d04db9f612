/* The shared command line: one loop over argv for every tool and app, so an option is
 * spelled, checked and reported the same way everywhere (docs/tools.md). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "private/rs_parse.h"
#include "cli_internal.h"

bool rs_cli_parse_u32(const char *text, uint32_t min, uint32_t max, uint32_t *out)
{
	RS_ASSERT(out);
	return rs_parse_u32(text, min, max, out);
}

bool rs_cli_parse_size(const char *text, uint32_t max, uint32_t *out_w, uint32_t *out_h)
{
	RS_ASSERT(out_w && out_h);
	return rs_parse_size(text, max, out_w, out_h);
}

int rs_cli_usage_error(const struct rs_cli *cli, const char *fmt, ...)
{
	RS_ASSERT(cli && fmt);
	char msg[RS_ERROR_MESSAGE_MAX];
	va_list args;
	va_start(args, fmt);
	vsnprintf(msg, sizeof msg, fmt, args);
	va_end(args);
	fprintf(stderr, "%s: %s (see --help)\n", cli->prog, msg);
	return RS_CLI_EXIT_USAGE;
}

int rs_cli_fail(const struct rs_cli *cli, const struct rs_error *err)
{
	RS_ASSERT(cli);
	fprintf(stderr, "%s: %s\n", cli->prog, err && err->message[0] ? err->message : "failed");
	return 1;
}

void rs_cli_note(const struct rs_cli *cli, const char *message)
{
	RS_ASSERT(cli);
	if (message && *message)
		fprintf(stderr, "%s: %s\n", cli->prog, message);
}

void rs_cli_wrote(const char *path)
{
	RS_ASSERT(path);
	printf("wrote %s\n", path);
	/* A caller piping stdout sees the name as soon as the file is there. */
	fflush(stdout);
}

enum rs_status rs_cli_make_dir(const char *path, struct rs_error *err)
{
	RS_ASSERT(path);
	size_t n = strlen(path);
	if (n == 0)
		return rs_error_set(err, RS_ERR_INVALID, "empty folder name");
	char *p = malloc(n + 1);
	if (!p)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory");
	memcpy(p, path, n + 1);
	enum rs_status st = RS_OK;
	/* Each prefix ending before a '/', then the whole path. */
	for (size_t i = 1; i <= n && st == RS_OK; ++i) {
		if (i < n && p[i] != '/')
			continue;
		char keep = p[i];
		p[i] = '\0';
		struct stat sb;
		if (stat(p, &sb) == 0) {
			if (!S_ISDIR(sb.st_mode))
				st = rs_error_set(err, RS_ERR_IO, "%s: exists and is not a folder",
				                  p);
		} else if (mkdir(p, 0777) != 0 && errno != EEXIST) {
			st = rs_error_set(err, RS_ERR_IO, "cannot make folder %s: %s", p,
			                  strerror(errno));
		}
		p[i] = keep;
	}
	free(p);
	return st;
}

bool rs_cli_listed(const char *keys, const char *key)
{
	if (!keys)
		return false;
	if (strcmp(keys, "*") == 0)
		return true;
	size_t n = strlen(key);
	for (const char *p = keys; *p;) {
		const char *end = strchr(p, ',');
		size_t m = end ? (size_t)(end - p) : strlen(p);
		if (m == n && strncmp(p, key, n) == 0)
			return true;
		p += m + (end ? 1 : 0);
	}
	return false;
}

static const struct rs_cli_option *find_option(const struct rs_cli *cli, const char *name,
                                               size_t len)
{
	for (size_t i = 0; i < cli->option_count; ++i)
		if (strlen(cli->options[i].name) == len &&
		    strncmp(cli->options[i].name, name, len) == 0)
			return &cli->options[i];
	return NULL;
}

/* A render option named --KEY this program takes, or NULL. */
static const struct rs_render_option *find_render(const struct rs_cli *cli, const char *name,
                                                  size_t len)
{
	char key[32];
	if (!cli->render || len < 3 || len - 2 >= sizeof key)
		return NULL;
	memcpy(key, name + 2, len - 2);
	key[len - 2] = '\0';
	const struct rs_render_option *o = rs_render_option_find(key);
	return o && rs_cli_listed(cli->render_keys, o->key) ? o : NULL;
}

/* Store `value` for `o`; false after reporting a usage error. */
static bool set_option(const struct rs_cli *cli, const struct rs_cli_option *o, const char *value)
{
	struct rs_error err = {0};
	switch (o->kind) {
	case RS_CLI_FLAG:
		*(bool *)o->out = true;
		return true;
	case RS_CLI_STRING:
		*(const char **)o->out = value;
		return true;
	case RS_CLI_U32: {
		uint32_t lo = o->min > 0 ? (uint32_t)o->min : 0u;
		uint32_t hi = o->max < 4294967295.0 ? (uint32_t)o->max : UINT32_MAX;
		if (rs_parse_u32(value, lo, hi, (uint32_t *)o->out))
			return true;
		rs_cli_usage_error(cli, "%s: '%s' is not a whole number in %u..%u", o->name, value,
		                   lo, hi);
		return false;
	}
	case RS_CLI_DOUBLE: {
		char *end = NULL;
		double v = value[0] ? strtod(value, &end) : NAN;
		if (end && *end == '\0' && isfinite(v) && v >= o->min && v <= o->max) {
			*(double *)o->out = v;
			return true;
		}
		rs_cli_usage_error(cli, "%s: '%s' is not a number in %g..%g", o->name, value,
		                   o->min, o->max);
		return false;
	}
	case RS_CLI_CALL:
		if (o->call(o->out, value, &err) == RS_OK)
			return true;
		rs_cli_usage_error(cli, "%s: %s", o->name, err.message);
		return false;
	}
	return false;
}

bool rs_cli_parse(struct rs_cli *cli, int argc, char **argv, int *out_exit)
{
	RS_ASSERT(cli && cli->prog && out_exit && (argc == 0 || argv));
	*out_exit = 0;
	cli->positional_count = 0;
	bool rest = false;
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i];
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			rs_cli_help(cli, stdout);
			return false;
		}
		if (!rest && strcmp(a, "--") == 0) { /* the rest are positionals, "-" or not */
			rest = true;
			continue;
		}
		/* "--name[=value]", or a short name the table spells out ("-o"). */
		bool named = !rest && ((a[0] == '-' && a[1] == '-') ||
		                       (a[0] == '-' && find_option(cli, a, strlen(a))));
		if (!named) {
			if (cli->positional_count < cli->positional_max) {
				cli->positional[cli->positional_count++] = a;
				continue;
			}
			*out_exit = rs_cli_usage_error(cli, "unexpected argument '%s'", a);
			return false;
		}
		const char *eq = a[1] == '-' ? strchr(a, '=') : NULL;
		size_t len = eq ? (size_t)(eq - a) : strlen(a);
		const struct rs_cli_option *o = find_option(cli, a, len);
		const struct rs_render_option *r = o ? NULL : find_render(cli, a, len);
		if (!o && !r) {
			*out_exit = rs_cli_usage_error(cli, "unknown option '%.*s'", (int)len, a);
			return false;
		}
		const char *value = NULL;
		if (o && o->kind == RS_CLI_FLAG) {
			if (eq) {
				*out_exit =
				    rs_cli_usage_error(cli, "%.*s takes no value", (int)len, a);
				return false;
			}
		} else if (eq) {
			value = eq + 1;
		} else if (i + 1 < argc) {
			value = argv[++i];
		} else {
			*out_exit = rs_cli_usage_error(cli, "option %s needs a value", a);
			return false;
		}
		if (o && !set_option(cli, o, value)) {
			*out_exit = RS_CLI_EXIT_USAGE;
			return false;
		}
		struct rs_error err = {0};
		if (r && rs_render_desc_set(cli->render, r->key, value, &err) != RS_OK) {
			*out_exit = rs_cli_usage_error(cli, "--%s", err.message);
			return false;
		}
	}
	return true;
}

enum rs_status rs_cli_check_output(const char *path, struct rs_error *err)
{
	RS_ASSERT(path);
	struct stat sb;
	if (!path[0])
		return rs_error_set(err, RS_ERR_INVALID, "empty output file name");
	if (stat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
		return rs_error_set(err, RS_ERR_IO, "cannot write %s: not a regular file", path);
	char dir[4096];
	if ((size_t)snprintf(dir, sizeof dir, "%s", path) >= sizeof dir)
		return rs_error_set(err, RS_ERR_INVALID, "output path too long");
	char *slash = strrchr(dir, '/');
	if (!slash)
		snprintf(dir, sizeof dir, ".");
	else
		slash[slash == dir ? 1 : 0] = '\0';
	if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode) || access(dir, W_OK) != 0)
		return rs_error_set(err, RS_ERR_IO, "cannot write %s: %s is not a writable folder",
		                    path, dir);
	return RS_OK;
}
