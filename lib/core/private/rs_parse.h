/*
 * Private to raystream (never installed): the one strict parser of whole numbers and
 * "WxH" sizes, shared by the render option setter (lib/render) and the command-line
 * module (lib/cli), so a number means the same on every command line and config string.
 */
#ifndef RS_PARSE_H
#define RS_PARSE_H

#include <stdbool.h>
#include <stdint.h>

/* The whole of `text` is a decimal number in [min, max] (no sign, no spaces). */
bool rs_parse_u32(const char *text, uint32_t min, uint32_t max, uint32_t *out);

/* "WxH" with both sides in [1, max]. */
bool rs_parse_size(const char *text, uint32_t max, uint32_t *out_w, uint32_t *out_h);

#endif
