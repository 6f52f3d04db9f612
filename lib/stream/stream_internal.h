/* Private to rs_stream: the per-type body codec (fields through private/rs_le.h). */
#ifndef RS_STREAM_INTERNAL_H
#define RS_STREAM_INTERNAL_H

#include <string.h>

#include "private/rs_le.h"
#include "raystream/rs_stream.h"

/* Largest payload a message of `type` may declare (frames: the fixed part plus
 * RS_STREAM_MAX_SIDE^2 * 4 raw bytes; the parser's buffer bounds it further). 0: unknown. */
uint32_t rs_stream_max_payload(uint32_t type);

/* Decode and validate one complete body. RS_ERR_PARSE for a length that does not fit the
 * layout, RS_ERR_BAD_DATA for a field out of range; `err` names it. */
enum rs_status rs_stream_decode_body(uint32_t type, const uint8_t *body, uint32_t length,
                                     struct rs_stream_msg *out, struct rs_error *err);

#endif
