/*
 * The real rs_hid_api: each entry calls the hidapi function of the same name.
 */
#include <hidapi.h>

#include "hid_api.h"

static int real_init(void *ctx)
{
	(void)ctx;
	return hid_init();
}

static void *real_open(void *ctx, unsigned short vid, unsigned short pid, const wchar_t *serial)
{
	(void)ctx;
	return hid_open(vid, pid, serial);
}

static int real_read_timeout(void *ctx, void *dev, unsigned char *data, size_t len, int ms)
{
	(void)ctx;
	return hid_read_timeout(dev, data, len, ms);
}

static void real_close(void *ctx, void *dev)
{
	(void)ctx;
	hid_close(dev);
}

static const wchar_t *real_error(void *ctx, void *dev)
{
	(void)ctx;
	return hid_error(dev);
}

const struct rs_hid_api *rs_hid_api_default(void)
{
	static const struct rs_hid_api api = {
	    .init = real_init,
	    .open = real_open,
	    .read_timeout = real_read_timeout,
	    .close = real_close,
	    .error = real_error,
	};
	return &api;
}
