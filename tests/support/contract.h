/* Contract-violation checks for tests: run one call with an RS_ASSERT handler that jumps
 * back here instead of aborting, and assert that the check fired. */
#ifndef RS_TEST_CONTRACT_H
#define RS_TEST_CONTRACT_H

#include <setjmp.h>
#include <stdbool.h>

extern jmp_buf rs_contract_jump;

/** Install the jumping handler and forget any earlier violation. */
void rs_contract_arm(void);
/** Restore the default handler; true when a contract check fired since rs_contract_arm(). */
bool rs_contract_disarm(void);
/** Text of the last failed condition ("" if none). */
const char *rs_contract_last_expr(void);

/* The call must hit an RS_ASSERT: nothing after the failed check runs (it jumps back). */
#define RS_EXPECT_CONTRACT_VIOLATION(call)                                                         \
	do {                                                                                       \
		rs_contract_arm();                                                                 \
		if (setjmp(rs_contract_jump) == 0) {                                               \
			call;                                                                      \
		}                                                                                  \
		if (!rs_contract_disarm())                                                         \
			fail_msg("no contract violation reported by: %s", #call);                  \
	} while (0)

#endif
