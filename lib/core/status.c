/* Status names and the caller-owned error record. */
#include "raystream/rs_status.h"

#include <stdio.h>
#include <string.h>

const char *rs_status_name(enum rs_status status)
{
	switch (status) {
	case RS_OK:
		return "RS_OK";
	case RS_TIMEOUT:
		return "RS_TIMEOUT";
	case RS_END:
		return "RS_END";
	case RS_ERR_INVALID:
		return "RS_ERR_INVALID";
	case RS_ERR_NO_MEMORY:
		return "RS_ERR_NO_MEMORY";
	case RS_ERR_IO:
		return "RS_ERR_IO";
	case RS_ERR_PARSE:
		return "RS_ERR_PARSE";
	case RS_ERR_BAD_DATA:
		return "RS_ERR_BAD_DATA";
	case RS_ERR_UNSUPPORTED:
		return "RS_ERR_UNSUPPORTED";
	case RS_ERR_NOT_FOUND:
		return "RS_ERR_NOT_FOUND";
	case RS_ERR_DISCONNECTED:
		return "RS_ERR_DISCONNECTED";
	case RS_ERR_LIMIT:
		return "RS_ERR_LIMIT";
	case RS_ERR_DEVICE:
		return "RS_ERR_DEVICE";
	case RS_ERR_DEGENERATE:
		return "RS_ERR_DEGENERATE";
	}
	return "RS_UNKNOWN_STATUS";
}

enum rs_status rs_error_setv(struct rs_error *err, enum rs_status status, const char *fmt,
                             va_list args)
{
	if (!err)
		return status;
	err->status = status;
	vsnprintf(err->message, sizeof err->message, fmt ? fmt : "", args);
	/* One line, always: callers print it as is. */
	for (char *c = err->message; *c; ++c)
		if (*c == '\n' || *c == '\r')
			*c = ' ';
	return status;
}

enum rs_status rs_error_set(struct rs_error *err, enum rs_status status, const char *fmt, ...)
{
	va_list args;
	va_start(args, fmt);
	rs_error_setv(err, status, fmt, args);
	va_end(args);
	return status;
}

void rs_error_clear(struct rs_error *err)
{
	if (!err)
		return;
	err->status = RS_OK;
	err->message[0] = '\0';
}

enum rs_status rs_error_prefix(struct rs_error *err, enum rs_status status, const char *fmt, ...)
{
	if (!err)
		return status;
	char context[RS_ERROR_MESSAGE_MAX];
	char old[RS_ERROR_MESSAGE_MAX];
	va_list args;
	va_start(args, fmt);
	vsnprintf(context, sizeof context, fmt ? fmt : "", args);
	va_end(args);
	memcpy(old, err->message, sizeof old);
	old[sizeof old - 1] = '\0';
	return rs_error_set(err, status, "%s: %s", context, old);
}
