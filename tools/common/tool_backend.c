/* rs_tool_backend_name(), apart from tool_common.c: only the tools that open renderers link
 * it (and with it the GL libraries; a tracker tool starting up would load them for
 * nothing). */
#include <stdio.h>

#include "raystream/rs_renderers.h"
#include "tool_common.h"

const char *rs_tool_backend_name(const struct rs_cli *cli, const struct rs_render_desc *desc,
                                 struct rs_error *err)
{
	static char name[16];
	struct rs_render_desc d = *desc;
	d.width = d.height = 8;
	struct rs_renderer *r = NULL;
	struct rs_error note = {0};
	if (rs_renderer_open_noted(NULL, &d, &r, &note, err) != RS_OK)
		return NULL;
	rs_cli_note(cli, note.message);
	snprintf(name, sizeof name, "%s", rs_renderer_backend(r));
	rs_renderer_destroy(&r);
	return name;
}
