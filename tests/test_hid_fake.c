/* rs_hid at its hidapi boundary: a fake device behind struct rs_hid_api. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <wchar.h>
#include <cmocka.h>

#ifdef RS_HAVE_HID
#include "hid/hid_api.h"

/* A fake HID tracker: a queue of reports, plug state, and call counters. */
struct fake_hid {
	int plugged;
	int open_handles;
	int opens, closes, inits;
	wchar_t last_serial[32];
	int got_serial;
	unsigned char reports[8][64];
	int report_len[8];
	int n, next;
	int dev_token;
};

static int f_init(void *ctx)
{
	((struct fake_hid *)ctx)->inits++;
	return 0;
}

static void *f_open(void *ctx, unsigned short vid, unsigned short pid, const wchar_t *serial)
{
	struct fake_hid *f = ctx;
	if (!f->plugged || vid != 0x1234 || pid != 0xabcd)
		return NULL;
	f->got_serial = serial != NULL;
	if (serial)
		wcsncpy(f->last_serial, serial, 31);
	f->opens++;
	f->open_handles++;
	return &f->dev_token;
}

static int f_read(void *ctx, void *dev, unsigned char *data, size_t len, int ms)
{
	struct fake_hid *f = ctx;
	assert_ptr_equal(dev, &f->dev_token);
	if (!f->plugged)
		return -1;
	if (f->next >= f->n)
		return 0;
	int n = f->report_len[f->next];
	assert_true((size_t)n <= len);
	memcpy(data, f->reports[f->next++], (size_t)n);
	return n;
}

static void f_close(void *ctx, void *dev)
{
	struct fake_hid *f = ctx;
	f->closes++;
	f->open_handles--;
}

static const wchar_t *f_error(void *ctx, void *dev)
{
	return L"fake hid: unplugged";
}

static struct fake_hid fake;
static struct rs_hid_api api = {&fake, f_init, f_open, f_read, f_close, f_error};

static int setup(void **state)
{
	memset(&fake, 0, sizeof fake);
	fake.plugged = 1;
	return 0;
}

static void push_report(uint32_t seq, int len)
{
	struct rs_marker_sample s = {.sequence = seq, .marker_count = 3};
	s.markers[1].flags = RS_MARKER_VALID;
	s.markers[1].position[2] = 1.25;
	memset(fake.reports[fake.n], 0, 64);
	assert_int_equal(rs_proto_encode(&s, fake.reports[fake.n], NULL), RS_OK);
	fake.report_len[fake.n++] = len;
}

static struct rs_track_source *open_fake(const char *serial)
{
	struct rs_hid_desc d = {.vid = 0x1234, .pid = 0xabcd, .serial = serial};
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_hid_open_api(&d, &api, &src, NULL), RS_OK);
	return src;
}

static void reports_become_samples(void **state)
{
	/* 64-byte reports carry a 62-byte frame plus padding: the padding is not garbage. */
	push_report(1, 64);
	push_report(2, 64);
	push_report(3, RS_PROTO_FRAME_SIZE); /* devices may also send the bare frame */
	struct rs_track_source *src = open_fake(NULL);
	struct rs_marker_sample s;
	for (uint32_t i = 1; i <= 3; i++) {
		assert_int_equal(rs_track_source_read(src, &s, 10, NULL), RS_OK);
		assert_int_equal(s.sequence, i);
		assert_true(s.markers[1].position[2] == 1.25);
	}
	assert_int_equal(rs_track_source_read(src, &s, 10, NULL), RS_TIMEOUT);
	struct rs_track_source_stats st;
	rs_track_source_get_stats(src, &st);
	assert_int_equal(rs_proto_stats_faults(&st.proto), 0);
	assert_false(fake.got_serial);
	rs_track_source_destroy(&src);
	assert_int_equal(fake.open_handles, 0);
}

static void corrupt_report_is_counted(void **state)
{
	push_report(1, 64);
	fake.reports[0][20] ^= 0x40;
	push_report(2, 64);
	struct rs_track_source *src = open_fake(NULL);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 10, NULL), RS_OK);
	assert_int_equal(s.sequence, 2);
	struct rs_track_source_stats st;
	rs_track_source_get_stats(src, &st);
	assert_int_equal(st.proto.crc_errors, 1);
	rs_track_source_destroy(&src);
}

static void serial_number_is_passed(void **state)
{
	struct rs_track_source *src = open_fake("AB12");
	assert_true(fake.got_serial);
	assert_true(wcscmp(fake.last_serial, L"AB12") == 0);
	rs_track_source_destroy(&src);
}

/* A serial that could never match (cut to fit, or bytes widened as Latin-1) is refused
 * with a message instead of being tried. */
static void unusable_serial_is_invalid(void **state)
{
	char longer[200];
	memset(longer, 'A', sizeof longer - 1);
	longer[sizeof longer - 1] = '\0';
	const char *bad[] = {longer, "caf\xc3\xa9"};
	for (int i = 0; i < 2; i++) {
		struct rs_hid_desc d = {.vid = 0x1234, .pid = 0xabcd, .serial = bad[i]};
		struct rs_track_source *src = NULL;
		struct rs_error err;
		assert_int_equal(rs_hid_open_api(&d, &api, &src, &err), RS_ERR_INVALID);
		assert_null(src);
		assert_non_null(strstr(err.message, "serial"));
	}
	assert_int_equal(fake.opens, 0);
}

static void unplug_and_replug(void **state)
{
	push_report(1, 64);
	struct rs_track_source *src = open_fake(NULL);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 10, NULL), RS_OK);
	fake.plugged = 0;
	assert_int_equal(rs_track_source_read(src, &s, 10, NULL), RS_ERR_DISCONNECTED);
	assert_non_null(strstr(rs_track_source_last_error(src), "unplugged"));
	assert_int_equal(fake.open_handles, 0); /* the dead handle was closed */
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_ERR_NOT_FOUND);
	fake.plugged = 1;
	push_report(1, 64); /* the device restarted its sequence: accepted after reopen */
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 10, NULL), RS_OK);
	assert_int_equal(s.sequence, 1);
	rs_track_source_destroy(&src);
	assert_int_equal(fake.open_handles, 0);
	assert_int_equal(fake.opens, 2);
}

static void missing_device_is_not_found(void **state)
{
	fake.plugged = 0;
	struct rs_hid_desc d = {.vid = 0x1234, .pid = 0xabcd};
	struct rs_track_source *src = NULL;
	struct rs_error err;
	assert_int_equal(rs_hid_open_api(&d, &api, &src, &err), RS_ERR_NOT_FOUND);
	assert_non_null(strstr(err.message, "1234:abcd"));
	assert_null(src);
}

static void uri_parsing(void **state)
{
	struct rs_hid_desc d;
	char serial[16];
	struct rs_error err;
	assert_int_equal(rs_hid_parse_uri("1234:ABCD", &d, serial, sizeof serial, NULL), RS_OK);
	assert_true(d.vid == 0x1234 && d.pid == 0xabcd && d.serial == NULL);
	assert_int_equal(rs_hid_parse_uri("5:6:SN-001", &d, serial, sizeof serial, NULL), RS_OK);
	assert_true(d.vid == 5 && d.pid == 6);
	assert_string_equal(d.serial, "SN-001");
	const char *bad[] = {"",        "1234",   "1234:", ":abcd",
	                     "12345:1", "12g4:1", "1:2:",  "1:2:this-serial-is-too-long"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_int_equal(rs_hid_parse_uri(bad[i], &d, serial, sizeof serial, &err),
		                 RS_ERR_PARSE);
		assert_true(err.message[0] != '\0');
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test_setup(reports_become_samples, setup),
	    cmocka_unit_test_setup(corrupt_report_is_counted, setup),
	    cmocka_unit_test_setup(serial_number_is_passed, setup),
	    cmocka_unit_test_setup(unusable_serial_is_invalid, setup),
	    cmocka_unit_test_setup(unplug_and_replug, setup),
	    cmocka_unit_test_setup(missing_device_is_not_found, setup),
	    cmocka_unit_test_setup(uri_parsing, setup),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
	return 0; /* hid backend not built: nothing to test */
}
#endif
