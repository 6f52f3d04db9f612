/* Second half of the none builder's 100,000 Cow1 rays (see test_cowrays_none.c). */
#define COW_NONE_BEGIN (COW_RAYS / 2)
#define COW_NONE_END COW_RAYS
#include "test_cowrays_none.c"
