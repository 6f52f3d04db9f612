/* Shared by the raystream command-line tools (public library headers only). */
#ifndef RS_TOOL_COMMON_H
#define RS_TOOL_COMMON_H

#include <cjson/cJSON.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_bvh.h"
#include "raystream/rs_cli.h"
#include "raystream/rs_image.h"
#include "raystream/rs_load.h"
#include "raystream/rs_pack.h"
#include "raystream/rs_render.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_scenegen.h"
#include "raystream/rs_status.h"
#include "raystream/rs_trace.h"

/* Process CPU time (user + system, all threads) in milliseconds. */
double rs_tool_cpu_ms(void);

/* qsort comparator for doubles, ascending. */
int rs_tool_cmp_double(const void *a, const void *b);
/* Median of v[0..n) (n > 0; the mean of the middle two when n is even). Sorts v in place. */
double rs_tool_median(double *v, uint32_t n);

/* Strict number parsing: the whole string, in [min, max]. */
int rs_tool_parse_u32(const char *text, uint32_t min, uint32_t max, uint32_t *out);
/* "WxH" with both sides in [1, RS_IMAGE_MAX_SIDE]. */
int rs_tool_parse_size(const char *text, uint32_t *out_w, uint32_t *out_h);

/* --reflections: "trace", "envmap" or "interreflect[:BOUNCES]" (1..RS_RENDER_MAX_BOUNCES;
 * without it 0, the default). Returns 1, or 0 when `text` is none of these. */
int rs_tool_parse_reflections(const char *text, enum rs_reflection_mode *mode, uint32_t *bounces);
/* "--nodes FORMAT[:ORDERS]": compact|paper, directional|octant|single (rs_pack.h) into pack's
 * nodes and orders; 1 on success, 0 when the text names neither. */
int rs_tool_parse_nodes(const char *text, struct rs_pack_desc *pack);
/* The same spelling for a pack descriptor ("compact:directional"), into out (size bytes). */
const char *rs_tool_nodes_name(const struct rs_pack_desc *pack, char *out, size_t size);
/* "--scene-storage auto|2d|buffer" (rs_scene_storage); 1 on success, 0 otherwise. */
int rs_tool_parse_storage(const char *text, enum rs_scene_storage *out);
/* The same spelling ("buffer"). */
const char *rs_tool_storage_name(enum rs_scene_storage storage);
/* The same spelling for a descriptor ("interreflect:2"), into out (size bytes). */
const char *rs_tool_reflections_name(const struct rs_render_desc *desc, char *out, size_t size);
/* The shadow mode's word ("rays", "map", "none"; a map's size and filter left out). */
const char *rs_tool_shadows_name(enum rs_shadow_mode shadows);

/* The backend `desc` asks for (desc->backend; NULL: auto) as this machine opens it: one
 * 8x8 renderer is opened and closed so "auto" is resolved once, its fallback note (if any)
 * goes to stderr through rs_cli_note(), and every row of a table can name the backend.
 * Returns a static name ("egl"), or NULL with `err` set when it cannot be opened. */
const char *rs_tool_backend_name(const struct rs_cli *cli, const struct rs_render_desc *desc,
                                 struct rs_error *err);

/* The one-letter spellings a tool keeps ("-n" for "--count"): each argv entry equal to
 * map[i][0] becomes map[i][1] in place, before rs_cli_parse() sees it, so the long option
 * is the one that is parsed, checked and named in errors. */
void rs_tool_long_options(int argc, char **argv, const char *const (*map)[2], size_t count);

/* Write text through a temporary file and rename (never a partial file). */
enum rs_status rs_tool_write_text(const char *path, const char *text, struct rs_error *err);

/* Write a JSON document through a temporary file and rename (never a partial file). */
enum rs_status rs_tool_write_json(const char *path, const cJSON *doc, struct rs_error *err);

#endif
