/* Keeps rs_testsupport non-empty when no other support file exists. */
void rs_testsupport_empty(void);
void rs_testsupport_empty(void)
{
}
