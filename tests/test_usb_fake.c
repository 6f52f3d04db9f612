/* rs_usb at its libusb boundary: a fake device behind struct rs_usb_api. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#ifdef RS_HAVE_USB
#include "usb/usb_api.h"

/* A fake bulk-endpoint tracker: a byte stream handed out in transfers of `chunk`. */
struct fake_usb {
	int plugged, has_endpoint, claim_error;
	int handles, claimed, inits, exits;
	unsigned last_timeout;
	int last_len;
	uint8_t stream[1024];
	size_t len, pos, chunk;
	int token;
};

static struct fake_usb fake;

static int f_init(void *ctx, void **out)
{
	fake.inits++;
	*out = &fake;
	return 0;
}

static void f_exit(void *ctx, void *usb)
{
	fake.exits++;
}

static void *f_open(void *ctx, void *usb, uint16_t vid, uint16_t pid)
{
	if (!fake.plugged || vid != 0x0483 || pid != 0x5740)
		return NULL;
	fake.handles++;
	return &fake.token;
}

static int f_find(void *ctx, void *h, int *itf, uint8_t *ep, int *interrupt)
{
	if (!fake.has_endpoint)
		return RS_USB_NOT_FOUND;
	*itf = 1;
	*ep = 0x81;
	*interrupt = 0;
	return 0;
}

static int f_claim(void *ctx, void *h, int itf)
{
	if (fake.claim_error)
		return fake.claim_error;
	fake.claimed++;
	return 0;
}

static int f_transfer(void *ctx, void *h, uint8_t ep, int interrupt, unsigned char *data, int len,
                      int *out, unsigned timeout)
{
	assert_int_equal(ep, 0x81);
	fake.last_timeout = timeout;
	fake.last_len = len;
	*out = 0;
	if (!fake.plugged)
		return RS_USB_NO_DEVICE;
	size_t n = fake.len - fake.pos;
	if (n == 0)
		return RS_USB_TIMEOUT;
	if (n > fake.chunk)
		n = fake.chunk;
	if (n > (size_t)len)
		n = (size_t)len;
	memcpy(data, fake.stream + fake.pos, n);
	fake.pos += n;
	*out = (int)n;
	return 0;
}

static void f_release(void *ctx, void *h, int itf)
{
	fake.claimed--;
}

static void f_close(void *ctx, void *h)
{
	fake.handles--;
}

/* No max_packet_size: the backend falls back to 512-byte reads. */
static const struct rs_usb_api api = {NULL,    f_init,     f_exit,    f_open,  f_find,
                                      f_claim, f_transfer, f_release, f_close, NULL};

static int setup(void **state)
{
	memset(&fake, 0, sizeof fake);
	fake.plugged = 1;
	fake.has_endpoint = 1;
	fake.chunk = 64;
	return 0;
}

static void push(uint32_t seq)
{
	struct rs_marker_sample s = {.sequence = seq, .marker_count = 3};
	assert_int_equal(rs_proto_encode(&s, fake.stream + fake.len, NULL), RS_OK);
	fake.len += RS_PROTO_FRAME_SIZE;
}

static struct rs_track_source *open_fake(void)
{
	struct rs_usb_desc d = {.vid = 0x0483, .pid = 0x5740};
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_usb_open_api(&d, &api, &src, NULL), RS_OK);
	return src;
}

static void bulk_stream_becomes_samples(void **state)
{
	/* 64-byte packets do not align with 62-byte frames: frames span transfers. */
	for (uint32_t i = 0; i < 10; i++)
		push(i);
	struct rs_track_source *src = open_fake();
	assert_int_equal(fake.claimed, 1);
	struct rs_marker_sample s;
	for (uint32_t i = 0; i < 10; i++) {
		assert_int_equal(rs_track_source_read(src, &s, 20, NULL), RS_OK);
		assert_int_equal(s.sequence, i);
	}
	assert_int_equal(rs_track_source_read(src, &s, 20, NULL), RS_TIMEOUT);
	rs_track_source_destroy(&src);
	assert_int_equal(fake.claimed, 0);
	assert_int_equal(fake.handles, 0);
	assert_int_equal(fake.exits, 1);
}

static int f_mps(void *ctx, void *h, uint8_t ep)
{
	return ep == 0x81 ? 64 : RS_USB_NOT_FOUND;
}

/* Reads are one max-size packet long: a 512-byte read of a full-speed device that fills
 * its 64-byte packets would wait for 8 of them. Without the query: 512 bytes. */
static void reads_are_one_packet_long(void **state)
{
	struct rs_usb_api with_mps = api;
	with_mps.max_packet_size = f_mps;
	struct rs_usb_desc d = {.vid = 0x0483, .pid = 0x5740};
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_usb_open_api(&d, &with_mps, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_TIMEOUT);
	assert_int_equal(fake.last_len, 64);
	rs_track_source_destroy(&src);
	src = open_fake();
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_TIMEOUT);
	assert_int_equal(fake.last_len, 512);
	rs_track_source_destroy(&src);
}

static void poll_uses_shortest_libusb_timeout(void **state)
{
	/* libusb reads a 0 ms timeout as "wait forever": a poll must ask for 1 ms. */
	struct rs_track_source *src = open_fake();
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_TIMEOUT);
	assert_int_equal(fake.last_timeout, 1);
	rs_track_source_destroy(&src);
}

static void unplug_and_replug(void **state)
{
	push(1);
	struct rs_track_source *src = open_fake();
	struct rs_marker_sample s;
	assert_int_equal(rs_track_source_read(src, &s, 20, NULL), RS_OK);
	fake.plugged = 0;
	assert_int_equal(rs_track_source_read(src, &s, 20, NULL), RS_ERR_DISCONNECTED);
	assert_non_null(strstr(rs_track_source_last_error(src), "NO_DEVICE"));
	assert_int_equal(fake.handles, 0);
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_ERR_NOT_FOUND);
	fake.plugged = 1;
	push(1);
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 20, NULL), RS_OK);
	assert_int_equal(s.sequence, 1);
	rs_track_source_destroy(&src);
	assert_int_equal(fake.handles, 0);
	assert_int_equal(fake.claimed, 0);
}

static void open_failures(void **state)
{
	struct rs_usb_desc d = {.vid = 0x0483, .pid = 0x5740};
	struct rs_track_source *src = NULL;
	struct rs_error err;
	fake.has_endpoint = 0;
	assert_int_equal(rs_usb_open_api(&d, &api, &src, &err), RS_ERR_UNSUPPORTED);
	fake.has_endpoint = 1;
	fake.claim_error = RS_USB_BUSY;
	assert_int_equal(rs_usb_open_api(&d, &api, &src, &err), RS_ERR_DEVICE);
	assert_non_null(strstr(err.message, "claim"));
	fake.claim_error = 0;
	d.pid = 1;
	assert_int_equal(rs_usb_open_api(&d, &api, &src, &err), RS_ERR_NOT_FOUND);
	assert_null(src);
	assert_int_equal(fake.handles, 0);
	assert_int_equal(fake.inits, fake.exits);
}

static void uri_parsing(void **state)
{
	struct rs_usb_desc d;
	struct rs_error err;
	assert_int_equal(rs_usb_parse_uri("0483:5740", &d, NULL), RS_OK);
	assert_true(d.vid == 0x0483 && d.pid == 0x5740);
	const char *bad[] = {"",      "0483", "0483:",  ":5740",  "10000:1", "04z3:1",
	                     "1:2:3", "-1:2", "0x12:1", "1:0x34", "\t1:2",   "1:+2"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		assert_int_equal(rs_usb_parse_uri(bad[i], &d, &err), RS_ERR_PARSE);
		assert_true(err.message[0] != '\0');
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test_setup(bulk_stream_becomes_samples, setup),
	    cmocka_unit_test_setup(poll_uses_shortest_libusb_timeout, setup),
	    cmocka_unit_test_setup(reads_are_one_packet_long, setup),
	    cmocka_unit_test_setup(unplug_and_replug, setup),
	    cmocka_unit_test_setup(open_failures, setup),
	    cmocka_unit_test_setup(uri_parsing, setup),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
#else
int main(void)
{
	return 0; /* usb backend not built: nothing to test */
}
#endif
