/**
 * @file rs_cli.h
 * The command line every raystream tool and app shares: one option parser (a table of
 * options, the render options of rs_render.h by key), --help with every default, a usage
 * error that names the option and its valid values (exit 2), `--out DIR` folders created,
 * and outputs named on stdout ("wrote PATH").
 *
 *   const char *scene = NULL, *out = NULL;
 *   struct rs_render_desc desc = {0};
 *   const struct rs_cli_option opts[] = {
 *       RS_CLI_STRING_OPT("--scene", &scene, "SCENE", "box, mirrors, cowN or a mesh file"),
 *       RS_CLI_STRING_OPT("--out", &out, "FILE.png", "image"),
 *   };
 *   struct rs_cli cli = {.prog = "raystream-x", .usage = "--scene SCENE [options]",
 *                        .options = opts, .option_count = 2,
 *                        .render = &desc, .render_keys = "backend,size,passes"};
 *   int code;
 *   if (!rs_cli_parse(&cli, argc, argv, &code))
 *           return code;                   (0 after --help, 2 after a usage error)
 *
 * Unlike the rest of the library this module writes to stdout and stderr, because that
 * is its job; it never exits. Every message is one line, prefixed with the program name.
 */
#ifndef RS_CLI_H
#define RS_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "raystream/rs_render.h"
#include "raystream/rs_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Exit status of a usage error (an unknown option, a value out of range). */
#define RS_CLI_EXIT_USAGE 2

/** What an option's `out` points to. */
enum rs_cli_kind {
	RS_CLI_FLAG = 0,   /**< bool; takes no value */
	RS_CLI_STRING = 1, /**< const char * (points into argv) */
	RS_CLI_U32 = 2,    /**< uint32_t in [min, max] */
	RS_CLI_DOUBLE = 3, /**< double, finite, in [min, max] */
	RS_CLI_CALL = 4,   /**< call(out, value, err) parses the value itself */
};

/** One option of a program (the render options come from rs_render.h, see rs_cli). */
struct rs_cli_option {
	const char *name; /**< "--frames" (or a short "-o") */
	enum rs_cli_kind kind;
	void *out;
	const char *arg;  /**< the value's name in --help ("N", "FILE"); NULL for a flag */
	const char *help; /**< one line */
	/** RS_CLI_U32 / RS_CLI_DOUBLE: the valid range, named in the error message. */
	double min, max;
	/** The default as --help shows it; NULL: the value `out` holds before parsing (none
	 * for a NULL string, a false flag or RS_CLI_CALL). */
	const char *fallback;
	/** RS_CLI_CALL: parse `value` into `out`; RS_ERR_INVALID with a message naming the
	 * valid values (the option name is prefixed). */
	enum rs_status (*call)(void *out, const char *value, struct rs_error *err);
};

/** Table rows without naming every field (-Wmissing-field-initializers stays quiet). */
#define RS_CLI_FLAG_OPT(NAME, OUT, HELP)                                                           \
	{                                                                                          \
		.name = (NAME), .kind = RS_CLI_FLAG, .out = (OUT), .help = (HELP)                  \
	}
#define RS_CLI_STRING_OPT(NAME, OUT, ARG, HELP)                                                    \
	{                                                                                          \
		.name = (NAME), .kind = RS_CLI_STRING, .out = (OUT), .arg = (ARG), .help = (HELP)  \
	}
/* A bound spelled as its value, a macro expanded first ("1..64", not "1..PEER_MAX_REPEATS"). */
#define RS_CLI__STR(x) RS_CLI__STR_(x)
#define RS_CLI__STR_(x) #x
#define RS_CLI_U32_OPT(NAME, OUT, MIN, MAX, HELP)                                                  \
	{                                                                                          \
		.name = (NAME), .kind = RS_CLI_U32, .out = (OUT),                                  \
		.arg = RS_CLI__STR(MIN) ".." RS_CLI__STR(MAX), .help = (HELP), .min = (MIN),       \
		.max = (MAX)                                                                       \
	}
#define RS_CLI_DOUBLE_OPT(NAME, OUT, ARG, MIN, MAX, HELP)                                          \
	{                                                                                          \
		.name = (NAME), .kind = RS_CLI_DOUBLE, .out = (OUT), .arg = (ARG), .help = (HELP), \
		.min = (MIN), .max = (MAX)                                                         \
	}
#define RS_CLI_CALL_OPT(NAME, OUT, CALL, ARG, HELP)                                                \
	{                                                                                          \
		.name = (NAME), .kind = RS_CLI_CALL, .out = (OUT), .call = (CALL), .arg = (ARG),   \
		.help = (HELP)                                                                     \
	}

/** A program's command line. */
struct rs_cli {
	const char *prog;  /**< "raystream-render": the prefix of every message */
	const char *usage; /**< after "usage: PROG ", e.g. "--scene SCENE [options]" */
	const char *about; /**< text printed after the options by --help; NULL: none */
	const struct rs_cli_option *options;
	size_t option_count;
	/** Render options (rs_render_options()) are accepted as --KEY VALUE into *render:
	 * `render_keys` lists the keys, comma-separated ("backend,size,passes"), or "*" for
	 * every one; NULL or render NULL: none. */
	struct rs_render_desc *render;
	const char *render_keys;
	/** Arguments not starting with "--": up to positional_max of them into positional[]
	 * (their count into positional_count); with positional_max 0 they are refused.
	 * `positional_name` names them in --help ("SCENE..."). */
	const char **positional;
	size_t positional_max;
	size_t positional_count;
	const char *positional_name;
};

/**
 * Parse argv[1..argc): "--name value", "--name=value", flags, positionals; a short name
 * the table spells ("-o") takes its value as the next argument; after "--" every argument
 * is a positional; the last of a repeated option wins. "--help" / "-h" print the help (rs_cli_help)
 * on stdout. Returns true to go on; false with *out_exit = 0 after --help, RS_CLI_EXIT_USAGE after
 * a usage error, reported as one line on stderr ("PROG: --passes: '0' is not 1..64 (see --help)").
 */
bool rs_cli_parse(struct rs_cli *cli, int argc, char **argv, int *out_exit);

/** The help: usage line, every option with its values and default, then `about`. */
void rs_cli_help(const struct rs_cli *cli, FILE *to);

/** Report a usage error found after parsing: "PROG: MESSAGE (see --help)" on stderr;
 * returns RS_CLI_EXIT_USAGE. */
int rs_cli_usage_error(const struct rs_cli *cli, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/** Report a failure: "PROG: MESSAGE" on stderr (err's message, or "failed" when empty);
 * returns 1, the exit status of a run that failed on its input or environment. */
int rs_cli_fail(const struct rs_cli *cli, const struct rs_error *err);

/** One informational line on stderr, "PROG: MESSAGE" (for example the note of
 * rs_renderer_open_noted()); nothing for an empty message. */
void rs_cli_note(const struct rs_cli *cli, const char *message);

/** Name an output on stdout: "wrote PATH". Every file a program writes is named so. */
void rs_cli_wrote(const char *path);

/** Strict whole number: all of `text`, in [min, max]. */
bool rs_cli_parse_u32(const char *text, uint32_t min, uint32_t max, uint32_t *out);

/** "WxH" with both sides in [1, max]. */
bool rs_cli_parse_size(const char *text, uint32_t max, uint32_t *out_w, uint32_t *out_h);

/**
 * The `--out DIR` rule: create `path` and its parents as needed (mkdir -p, mode 0777 less
 * the umask). RS_ERR_IO naming the part that exists but is not a folder, or the folder
 * that could not be made and why.
 */
enum rs_status rs_cli_make_dir(const char *path, struct rs_error *err);

/**
 * Whether `path` can be written as a file later, checked without touching it: its folder
 * exists and is writable, and it is a regular file or nothing. Programs check every output
 * target at start, so a bad path fails before the work and not after it. RS_ERR_IO naming
 * the problem.
 */
enum rs_status rs_cli_check_output(const char *path, struct rs_error *err);

#ifdef __cplusplus
}
#endif
#endif
