/* --help: every option with its values and its default, so nothing a program assumes is
 * hidden from the user (the defaults shown are the values the program starts from). */
#include <string.h>

#include "cli_internal.h"

#define COLUMN 34

static void line(FILE *to, const char *name, const char *arg, const char *help, const char *def)
{
	int n = fprintf(to, "  %s%s%s", name, arg ? " " : "", arg ? arg : "");
	if (n >= COLUMN - 1)
		fprintf(to, "\n%*s", COLUMN, "");
	else
		fprintf(to, "%*s", COLUMN - n, "");
	fprintf(to, "%s", help ? help : "");
	if (def && *def)
		fprintf(to, " [%s]", def);
	fputc('\n', to);
}

/* The value an option holds before parsing, as text (its default), or NULL. */
static const char *current(const struct rs_cli_option *o, char *buf, size_t cap)
{
	if (o->fallback)
		return o->fallback;
	switch (o->kind) {
	case RS_CLI_STRING:
		return *(const char *const *)o->out;
	case RS_CLI_U32:
		snprintf(buf, cap, "%u", *(const uint32_t *)o->out);
		return buf;
	case RS_CLI_DOUBLE:
		snprintf(buf, cap, "%g", *(const double *)o->out);
		return buf;
	case RS_CLI_FLAG:
	case RS_CLI_CALL:
		break;
	}
	return NULL;
}

void rs_cli_help(const struct rs_cli *cli, FILE *to)
{
	RS_ASSERT(cli && to);
	fprintf(to, "usage: %s %s\n", cli->prog, cli->usage ? cli->usage : "[options]");
	fprintf(to, "options [default]:\n");
	char buf[64];
	for (size_t i = 0; i < cli->option_count; ++i) {
		const struct rs_cli_option *o = &cli->options[i];
		line(to, o->name, o->arg, o->help, current(o, buf, sizeof buf));
	}
	if (cli->render && cli->render_keys) {
		size_t count;
		const struct rs_render_option *r = rs_render_options(&count);
		char name[40];
		for (size_t i = 0; i < count; ++i) {
			if (!rs_cli_listed(cli->render_keys, r[i].key))
				continue;
			snprintf(name, sizeof name, "--%s", r[i].key);
			if (rs_render_desc_get(cli->render, r[i].key, buf, sizeof buf, NULL) !=
			    RS_OK)
				buf[0] = '\0';
			line(to, name, r[i].values, r[i].help, buf);
		}
	}
	line(to, "--help", NULL, "this text", NULL);
	if (cli->about)
		fprintf(to, "%s%s", cli->about,
		        cli->about[strlen(cli->about) - 1] == '\n' ? "" : "\n");
}
