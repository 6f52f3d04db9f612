/* The jumping RS_ASSERT handler behind RS_EXPECT_CONTRACT_VIOLATION. */
#include "contract.h"

#include <stdio.h>

#include "raystream/rs_status.h"

jmp_buf rs_contract_jump;
static bool g_fired;
static char g_expr[256];

static void jump_back(const char *expr, const char *file, int line, void *user)
{
	(void)file;
	(void)line;
	(void)user;
	g_fired = true;
	snprintf(g_expr, sizeof g_expr, "%s", expr);
	longjmp(rs_contract_jump, 1);
}

void rs_contract_arm(void)
{
	g_fired = false;
	g_expr[0] = '\0';
	rs_set_assert_handler(jump_back, NULL);
}

bool rs_contract_disarm(void)
{
	rs_set_assert_handler(NULL, NULL);
	return g_fired;
}

const char *rs_contract_last_expr(void)
{
	return g_expr;
}
