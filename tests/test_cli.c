/* rs_cli: the one option loop of the tools and apps (values, ranges, render options,
 * positionals, --help with defaults, usage errors) and the --out DIR rule. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "raystream/rs_cli.h"

struct opts {
	const char *scene;
	uint32_t frames;
	double rate;
	bool quiet;
	const char *out;
	struct rs_render_desc desc;
	const char *pos[2];
};

/* Parse argv (NULL-terminated) with stderr captured into `errbuf`; returns whether to go on. */
static bool parse(struct opts *o, struct rs_cli *cli, const char *const *args, int *code,
                  char *errbuf, size_t cap)
{
	static struct rs_cli_option table[5];
	const struct rs_cli_option t[5] = {
	    RS_CLI_STRING_OPT("--scene", &o->scene, "SCENE", "what to render"),
	    RS_CLI_U32_OPT("--frames", &o->frames, 1, 1000, "frames to time"),
	    RS_CLI_DOUBLE_OPT("--rate", &o->rate, "HZ", 0.5, 1000.0, "samples per second"),
	    RS_CLI_FLAG_OPT("--quiet", &o->quiet, "no progress"),
	    RS_CLI_STRING_OPT("-o", &o->out, "FILE", "output"),
	};
	memcpy(table, t, sizeof t);
	*cli = (struct rs_cli){.prog = "test-cli",
	                       .options = table,
	                       .option_count = 5,
	                       .render = &o->desc,
	                       .render_keys = "passes,lights,backend",
	                       .positional = o->pos,
	                       .positional_max = 2};
	int argc = 0;
	char *argv[16];
	argv[argc++] = "test-cli";
	for (; args[argc - 1]; ++argc)
		argv[argc] = (char *)args[argc - 1];
	fflush(stderr);
	FILE *tmp = tmpfile();
	int saved = dup(2);
	dup2(fileno(tmp), 2);
	bool go = rs_cli_parse(cli, argc, argv, code);
	fflush(stderr);
	dup2(saved, 2);
	close(saved);
	rewind(tmp);
	size_t n = fread(errbuf, 1, cap - 1, tmp);
	errbuf[n] = '\0';
	fclose(tmp);
	return go;
}

static void values_ranges_and_render_options(void **state)
{
	struct opts o = {.frames = 5};
	struct rs_cli cli;
	char err[512];
	int code = -1;
	const char *args[] = {"--scene",  "cow1", "--frames=7",   "--rate", "2.5", "--quiet",
	                      "--passes", "3",    "--lights=all", "a",      "b",   NULL};
	assert_true(parse(&o, &cli, args, &code, err, sizeof err));
	assert_string_equal(err, "");
	assert_string_equal(o.scene, "cow1");
	assert_int_equal(o.frames, 7);
	assert_true(o.rate == 2.5);
	assert_true(o.quiet);
	assert_int_equal(o.desc.passes, 3);
	assert_int_equal(o.desc.lights, 0);
	assert_int_equal(cli.positional_count, 2);
	assert_string_equal(o.pos[1], "b");
}

/* A short name from the table, and "--" ending the options. */
static void short_names_and_the_end_of_options(void **state)
{
	struct opts o = {0};
	struct rs_cli cli;
	char err[512];
	int code = -1;
	const char *args[] = {"-o", "rig.yaml", "--", "--quiet", NULL};
	assert_true(parse(&o, &cli, args, &code, err, sizeof err));
	assert_string_equal(o.out, "rig.yaml");
	assert_false(o.quiet);
	assert_int_equal(cli.positional_count, 1);
	assert_string_equal(o.pos[0], "--quiet");
}

static void usage_errors_name_the_problem_and_exit_2(void **state)
{
	static const struct {
		const char *args[4];
		const char *message;
	} cases[] = {
	    {{"--frames", "0"},
	     "test-cli: --frames: '0' is not a whole number in 1..1000 (see --help)\n"},
	    {{"--rate", "nan"},
	     "test-cli: --rate: 'nan' is not a number in 0.5..1000 (see --help)\n"},
	    {{"--passes", "0"}, "test-cli: --passes: '0' is not 1..64 (see --help)\n"},
	    {{"--bvh", "sah"}, "test-cli: unknown option '--bvh' (see --help)\n"},
	    {{"--bogus=1"}, "test-cli: unknown option '--bogus' (see --help)\n"},
	    {{"--scene"}, "test-cli: option --scene needs a value (see --help)\n"},
	    {{"--quiet=yes"}, "test-cli: --quiet takes no value (see --help)\n"},
	    {{"a", "b", "c"}, "test-cli: unexpected argument 'c' (see --help)\n"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
		struct opts o = {0};
		struct rs_cli cli;
		char err[512];
		int code = -1;
		assert_false(parse(&o, &cli, cases[i].args, &code, err, sizeof err));
		assert_int_equal(code, RS_CLI_EXIT_USAGE);
		assert_string_equal(err, cases[i].message);
	}
}

static void help_lists_every_option_with_its_default(void **state)
{
	struct opts o = {.frames = 5, .rate = 120.0, .desc = {.passes = 1}};
	struct rs_cli cli;
	char err[64];
	int code = -1;
	fflush(stdout);
	FILE *tmp = tmpfile();
	int saved = dup(1);
	dup2(fileno(tmp), 1);
	const char *args[] = {"--help", NULL};
	bool go = parse(&o, &cli, args, &code, err, sizeof err);
	fflush(stdout);
	dup2(saved, 1);
	close(saved);
	char out[4096];
	rewind(tmp);
	size_t n = fread(out, 1, sizeof out - 1, tmp);
	out[n] = '\0';
	fclose(tmp);
	assert_false(go);
	assert_int_equal(code, 0);
	assert_string_equal(err, "");
	assert_non_null(strstr(out, "usage: test-cli"));
	assert_non_null(strstr(out, "--frames 1..1000"));
	assert_non_null(strstr(out, "frames to time [5]"));
	assert_non_null(strstr(out, "[120]"));
	/* the program's own starting value, not the library's: this one starts at 1 pass */
	assert_non_null(strstr(out, "--passes 1..64"));
	assert_non_null(strstr(out, "ray segments per path [1]"));
	assert_non_null(strstr(out, "--lights 1..64|all"));
	assert_non_null(strstr(out, "[all]"));
	assert_non_null(strstr(out, "--backend auto|cpu|egl|osmesa"));
	assert_null(strstr(out, "--bvh")); /* not one this program takes */
}

static void out_folders_are_made_with_their_parents(void **state)
{
	char base[] = "/tmp/rs_cli_test_XXXXXX";
	assert_non_null(mkdtemp(base));
	char path[256], file[256];
	snprintf(path, sizeof path, "%s/a/b/c/", base);
	struct rs_error err = {0};
	assert_int_equal(rs_cli_make_dir(path, &err), RS_OK);
	struct stat st;
	assert_int_equal(stat(path, &st), 0);
	assert_true(S_ISDIR(st.st_mode));
	assert_int_equal(rs_cli_make_dir(path, &err), RS_OK); /* again: fine */
	snprintf(file, sizeof file, "%s/a/file", base);
	FILE *f = fopen(file, "w");
	assert_non_null(f);
	fclose(f);
	snprintf(path, sizeof path, "%s/a/file/d", base);
	assert_int_equal(rs_cli_make_dir(path, &err), RS_ERR_IO);
	assert_non_null(strstr(err.message, "file: exists and is not a folder"));
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf %s", base);
	assert_int_equal(system(cmd), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(values_ranges_and_render_options),
	    cmocka_unit_test(short_names_and_the_end_of_options),
	    cmocka_unit_test(usage_errors_name_the_problem_and_exit_2),
	    cmocka_unit_test(help_lists_every_option_with_its_default),
	    cmocka_unit_test(out_folders_are_made_with_their_parents),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
