/*
 * Pseudo-terminal pair for end-to-end tests of the serial path: the master side plays
 * the tracker, the slave path is opened like any serial device.
 */
#define _GNU_SOURCE /* ptsname_r */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

#include "raystream/rs_serial.h"

struct rs_serial_pty {
	int master;
	int slave_keep; /* keeps the pair alive (and the line raw) until a reader opens it */
	char path[128];
};

enum rs_status rs_serial_pty_create(struct rs_serial_pty **out, struct rs_error *err)
{
	RS_ASSERT(out);
	*out = NULL;
	struct rs_serial_pty *p = calloc(1, sizeof *p);
	if (!p)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "pty: out of memory");
	p->slave_keep = -1;
	p->master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
	if (p->master < 0 || grantpt(p->master) != 0 || unlockpt(p->master) != 0 ||
	    ptsname_r(p->master, p->path, sizeof p->path) != 0) {
		int e = errno;
		if (p->master >= 0)
			close(p->master);
		free(p);
		return rs_error_set(err, RS_ERR_IO, "pty: cannot create a pseudo-terminal: %s",
		                    strerror(e));
	}
	/* Raw from the start, so no byte is ever cooked (CR/LF, ^C, echo) on the way. */
	p->slave_keep = open(p->path, O_RDWR | O_NOCTTY | O_CLOEXEC);
	struct termios t;
	if (p->slave_keep < 0 || tcgetattr(p->slave_keep, &t) != 0) {
		int e = errno;
		rs_serial_pty_destroy(&p);
		return rs_error_set(err, RS_ERR_IO, "pty: cannot configure: %s", strerror(e));
	}
	cfmakeraw(&t);
	/* The master is non-blocking so that a write to a line nobody reads can time out
	 * (rs_serial_pty_write_timeout) instead of hanging the writer, signals included. */
	int fl = fcntl(p->master, F_GETFL);
	if (tcsetattr(p->slave_keep, TCSANOW, &t) != 0 || fl < 0 ||
	    fcntl(p->master, F_SETFL, fl | O_NONBLOCK) != 0) {
		int e = errno;
		rs_serial_pty_destroy(&p);
		return rs_error_set(err, RS_ERR_IO, "pty: cannot configure: %s", strerror(e));
	}
	*out = p;
	return RS_OK;
}

const char *rs_serial_pty_path(const struct rs_serial_pty *pty)
{
	return pty->path;
}

enum rs_status rs_serial_pty_write_timeout(struct rs_serial_pty *p, const uint8_t *data, size_t len,
                                           int timeout_ms, size_t *out_written,
                                           struct rs_error *err)
{
	RS_ASSERT(p && (data || len == 0));
	size_t done = 0;
	if (out_written)
		*out_written = 0;
	if (p->master < 0)
		return rs_error_set(err, RS_ERR_DISCONNECTED, "pty: master side closed");
	double t0 = rs_now_ms();
	enum rs_status st = RS_OK;
	while (done < len) {
		ssize_t n = write(p->master, data + done, len - done);
		if (n > 0) {
			done += (size_t)n;
			continue;
		}
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
			st = rs_error_set(err, RS_ERR_IO, "pty: write: %s", strerror(errno));
			break;
		}
		/* The line is full: wait for room, at most until the deadline. */
		int wait = -1;
		if (timeout_ms >= 0) {
			double spent = rs_now_ms() - t0;
			if (spent >= timeout_ms) {
				st = rs_error_set(err, RS_TIMEOUT, "pty: line full for %d ms",
				                  timeout_ms);
				break;
			}
			wait = (int)(timeout_ms - spent) + 1;
		}
		struct pollfd pfd = {.fd = p->master, .events = POLLOUT};
		if (poll(&pfd, 1, wait) < 0 && errno != EINTR) {
			st = rs_error_set(err, RS_ERR_IO, "pty: poll: %s", strerror(errno));
			break;
		}
	}
	if (out_written)
		*out_written = done;
	return st;
}

enum rs_status rs_serial_pty_write(struct rs_serial_pty *p, const uint8_t *data, size_t len,
                                   struct rs_error *err)
{
	return rs_serial_pty_write_timeout(p, data, len, -1, NULL, err);
}

void rs_serial_pty_hangup(struct rs_serial_pty *p)
{
	if (p && p->master >= 0) {
		close(p->master);
		p->master = -1;
	}
	if (p && p->slave_keep >= 0) {
		close(p->slave_keep);
		p->slave_keep = -1;
	}
}

void rs_serial_pty_destroy(struct rs_serial_pty **pty)
{
	if (!pty || !*pty)
		return;
	rs_serial_pty_hangup(*pty);
	free(*pty);
	*pty = NULL;
}
