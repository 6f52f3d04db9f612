/* Private to the cli module: shared by the parser and the help. */
#ifndef RS_CLI_INTERNAL_H
#define RS_CLI_INTERNAL_H

#include "raystream/rs_cli.h"

/* Whether `key` is one of the comma-separated `keys` ("*": all; NULL: none). */
bool rs_cli_listed(const char *keys, const char *key);

#endif
