/* The always-on contract check behind RS_ASSERT, with a replaceable handler. */
#include "raystream/rs_status.h"

#include <stdio.h>
#include <stdlib.h>

static rs_assert_handler g_handler;
static void *g_user;

void rs_set_assert_handler(rs_assert_handler handler, void *user)
{
	g_handler = handler;
	g_user = user;
}

void rs_assert_fail(const char *expr, const char *file, int line)
{
	if (g_handler)
		g_handler(expr, file, line, g_user);
	else
		/* The one place the library prints: the process is about to abort and there is
		 * no caller left to hand a status to. */
		fprintf(stderr, "raystream: contract violated: %s (%s:%d)\n", expr, file, line);
	abort();
}

void rs_free(void *ptr)
{
	free(ptr);
}
