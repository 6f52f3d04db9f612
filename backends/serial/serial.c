/*
 * Serial transport: open a tty in raw mode at a standard speed, read with poll().
 * Hang-ups (POLLHUP, EOF, EIO, ENXIO) become RS_ERR_DISCONNECTED.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

#include "raystream/rs_serial.h"

static const struct {
	int baud;
	speed_t code;
} bauds[] = {
    {9600, B9600},       {19200, B19200},   {38400, B38400},
    {57600, B57600},     {115200, B115200}, {230400, B230400},
#ifdef B460800
    {460800, B460800},
#endif
#ifdef B921600
    {921600, B921600},
#endif
#ifdef B1000000
    {1000000, B1000000},
#endif
#ifdef B2000000
    {2000000, B2000000},
#endif
#ifdef B3000000
    {3000000, B3000000},
#endif
#ifdef B4000000
    {4000000, B4000000},
#endif
};

static int baud_code(int baud, speed_t *out)
{
	for (size_t i = 0; i < sizeof bauds / sizeof bauds[0]; i++)
		if (bauds[i].baud == baud) {
			*out = bauds[i].code;
			return 1;
		}
	return 0;
}

bool rs_serial_is_baud_supported(int baud)
{
	speed_t c;
	return baud_code(baud, &c);
}

struct serial {
	int fd;
	char path[256];
	speed_t speed;
};

static enum rs_status serial_open_fd(struct serial *s, struct rs_error *err)
{
	int fd = open(s->path, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
	if (fd < 0)
		return rs_error_set(
		    err, errno == ENOENT || errno == ENXIO ? RS_ERR_NOT_FOUND : RS_ERR_IO,
		    "serial: cannot open %s: %s", s->path, strerror(errno));
	struct termios t;
	if (tcgetattr(fd, &t) != 0) {
		close(fd);
		return rs_error_set(err, RS_ERR_INVALID, "serial: %s is not a terminal", s->path);
	}
	cfmakeraw(&t);
	t.c_cflag |= CLOCAL | CREAD;
	t.c_cc[VMIN] = 0;
	t.c_cc[VTIME] = 0;
	if (cfsetispeed(&t, s->speed) != 0 || cfsetospeed(&t, s->speed) != 0 ||
	    tcsetattr(fd, TCSANOW, &t) != 0) {
		int e = errno;
		close(fd);
		return rs_error_set(err, RS_ERR_IO, "serial: cannot configure %s: %s", s->path,
		                    strerror(e));
	}
	tcflush(fd, TCIFLUSH); /* drop bytes that arrived before raw mode */
	s->fd = fd;
	return RS_OK;
}

static enum rs_status serial_read(void *impl, uint8_t *buf, size_t cap, int timeout_ms,
                                  size_t *out_n, struct rs_error *err)
{
	struct serial *s = impl;
	*out_n = 0;
	if (s->fd < 0)
		return rs_error_set(err, RS_ERR_DISCONNECTED, "serial: %s is closed", s->path);
	struct pollfd pfd = {.fd = s->fd, .events = POLLIN};
	int r = poll(&pfd, 1, timeout_ms);
	/* A signal ends this wait early; the stream source waits again for what is left of
	 * the caller's timeout (restarting poll() here would restart the whole timeout). */
	if (r < 0 && errno == EINTR)
		return rs_error_set(err, RS_TIMEOUT, "serial: interrupted");
	if (r < 0)
		return rs_error_set(err, RS_ERR_IO, "serial: poll on %s: %s", s->path,
		                    strerror(errno));
	if (r == 0)
		return rs_error_set(err, RS_TIMEOUT, "serial: timeout");
	ssize_t n = read(s->fd, buf, cap);
	if (n > 0) {
		*out_n = (size_t)n;
		return RS_OK;
	}
	int e = n < 0 ? errno : 0;
	int hup = (pfd.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0;
	/* With VMIN = VTIME = 0 a tty read of 0 only means "nothing now" unless poll() also
	 * saw a hang-up; EIO/ENXIO or a hang-up mean the line or device went away. */
	if (!hup && (n == 0 || e == EAGAIN || e == EINTR))
		return rs_error_set(err, RS_TIMEOUT, "serial: timeout");
	close(s->fd);
	s->fd = -1;
	return rs_error_set(err, RS_ERR_DISCONNECTED, "serial: %s disconnected%s%s", s->path,
	                    e ? ": " : "", e ? strerror(e) : "");
}

static enum rs_status serial_reopen(void *impl, struct rs_error *err)
{
	struct serial *s = impl;
	if (s->fd >= 0) {
		close(s->fd);
		s->fd = -1;
	}
	return serial_open_fd(s, err);
}

static void serial_destroy(void *impl)
{
	struct serial *s = impl;
	if (!s)
		return;
	if (s->fd >= 0)
		close(s->fd);
	free(s);
}

static const struct rs_track_transport serial_transport = {
    .read = serial_read,
    .reopen = serial_reopen,
    .destroy = serial_destroy,
};

enum rs_status rs_serial_open(const struct rs_serial_desc *desc,
                              struct rs_track_source **out_source, struct rs_error *err)
{
	RS_ASSERT(out_source);
	*out_source = NULL;
	RS_ASSERT(desc);
	if (!desc->path || !desc->path[0])
		return rs_error_set(err, RS_ERR_INVALID, "serial: no device path");
	int baud = desc->baud ? desc->baud : 115200;
	speed_t speed;
	if (!baud_code(baud, &speed))
		return rs_error_set(err, RS_ERR_INVALID, "serial: unsupported baud rate %d", baud);
	if (strlen(desc->path) >= sizeof((struct serial *)0)->path)
		return rs_error_set(err, RS_ERR_INVALID, "serial: device path too long");
	struct serial *s = calloc(1, sizeof *s);
	if (!s)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "serial: out of memory");
	snprintf(s->path, sizeof s->path, "%s", desc->path);
	s->speed = speed;
	s->fd = -1;
	enum rs_status st = serial_open_fd(s, err);
	if (st != RS_OK) {
		free(s);
		return st;
	}
	return rs_track_stream_create(&serial_transport, s, out_source, err);
}

enum rs_status rs_serial_parse_uri(const char *rest, char *path_buf, size_t path_cap,
                                   struct rs_serial_desc *out, struct rs_error *err)
{
	RS_ASSERT(rest && path_buf && out);
	memset(out, 0, sizeof *out);
	size_t plen = strcspn(rest, "?");
	if (plen == 0 || rest[0] != '/')
		return rs_error_set(
		    err, RS_ERR_PARSE,
		    "serial: expected serial:/dev/PATH[?baud=N], got 'serial:%.60s'", rest);
	if (plen + 1 > path_cap)
		return rs_error_set(err, RS_ERR_PARSE, "serial: device path too long");
	memcpy(path_buf, rest, plen);
	path_buf[plen] = '\0';
	out->path = path_buf;
	const char *q = rest + plen;
	while (*q) {
		q++; /* '?' or '&' */
		size_t len = strcspn(q, "&");
		if (len > 5 && !strncmp(q, "baud=", 5)) {
			long v = 0;
			size_t i = 5;
			for (; i < len && q[i] >= '0' && q[i] <= '9' && v < 100000000; i++)
				v = v * 10 + (q[i] - '0');
			if (i != len || !rs_serial_is_baud_supported((int)v))
				return rs_error_set(err, RS_ERR_PARSE,
				                    "serial: bad baud rate '%.*s'",
				                    (int)(len - 5 > 20 ? 20 : len - 5), q + 5);
			out->baud = (int)v;
		} else {
			return rs_error_set(err, RS_ERR_PARSE, "serial: unknown option '%.*s'",
			                    (int)(len > 40 ? 40 : len), q);
		}
		q += len;
	}
	return RS_OK;
}
