/* Sockets for the server and the viewer. IPv4 only: the paper's link is one Wi-Fi hop,
 * and loopback is what tests use. */
#define _POSIX_C_SOURCE 200809L
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_stream.h"

#include "app_net.h"

enum rs_status app_parse_hostport(const char *text, char *host, size_t host_cap, uint16_t *port,
                                  struct rs_error *err)
{
	const char *colon = strrchr(text, ':');
	if (!colon || colon == text || (size_t)(colon - text) >= host_cap)
		return rs_error_set(err, RS_ERR_PARSE, "'%s' is not HOST:PORT", text);
	char *end = NULL;
	errno = 0;
	long p = strtol(colon + 1, &end, 10);
	if (errno || !end || *end || colon[1] == '\0' || p < 0 || p > 65535)
		return rs_error_set(err, RS_ERR_PARSE, "'%s': port must be 0..65535", text);
	memcpy(host, text, (size_t)(colon - text));
	host[colon - text] = '\0';
	if (!strcmp(host, "localhost"))
		snprintf(host, host_cap, "127.0.0.1");
	struct in_addr a;
	if (inet_pton(AF_INET, host, &a) != 1)
		return rs_error_set(err, RS_ERR_PARSE, "'%s' is not an IPv4 address", host);
	*port = (uint16_t)p;
	return RS_OK;
}

void app_socket_setup(int fd, int sndbuf)
{
	int one = 1;
	fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
	fcntl(fd, F_SETFD, FD_CLOEXEC);
	setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
	if (sndbuf > 0)
		setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf);
}

/* The address and a fresh TCP socket for it. */
static enum rs_status open_socket(const char *host, uint16_t port, struct sockaddr_in *sa,
                                  int *out_fd, struct rs_error *err)
{
	memset(sa, 0, sizeof *sa);
	sa->sin_family = AF_INET;
	sa->sin_port = htons(port);
	if (inet_pton(AF_INET, host, &sa->sin_addr) != 1)
		return rs_error_set(err, RS_ERR_PARSE, "'%s' is not an IPv4 address", host);
	*out_fd = socket(AF_INET, SOCK_STREAM, 0);
	if (*out_fd < 0)
		return rs_error_set(err, RS_ERR_IO, "socket: %s", strerror(errno));
	return RS_OK;
}

enum rs_status app_listen(const char *host, uint16_t port, int *out_fd, uint16_t *out_port,
                          struct rs_error *err)
{
	struct sockaddr_in sa;
	int fd = -1;
	enum rs_status st = open_socket(host, port, &sa, &fd, err);
	if (st != RS_OK)
		return st;
	int one = 1;
	setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
	if (bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0 || listen(fd, 64) != 0) {
		int e = errno;
		close(fd);
		return rs_error_set(err, RS_ERR_IO, "cannot listen on %s:%u: %s", host, port,
		                    strerror(e));
	}
	socklen_t len = sizeof sa;
	getsockname(fd, (struct sockaddr *)&sa, &len);
	app_socket_setup(fd, 0);
	*out_fd = fd;
	*out_port = ntohs(sa.sin_port);
	return RS_OK;
}

enum rs_status app_connect(const char *host, uint16_t port, int timeout_ms, int *out_fd,
                           struct rs_error *err)
{
	struct sockaddr_in sa;
	int fd = -1;
	enum rs_status st = open_socket(host, port, &sa, &fd, err);
	if (st != RS_OK)
		return st;
	app_socket_setup(fd, 0);
	int rc = connect(fd, (struct sockaddr *)&sa, sizeof sa);
	if (rc != 0 && errno == EINPROGRESS) {
		struct pollfd p = {.fd = fd, .events = POLLOUT};
		rc = poll(&p, 1, timeout_ms) == 1 ? 0 : -1;
		int soerr = rc == 0 ? 0 : ETIMEDOUT;
		socklen_t l = sizeof soerr;
		if (rc == 0)
			getsockopt(fd, SOL_SOCKET, SO_ERROR, &soerr, &l);
		errno = soerr;
		rc = soerr ? -1 : 0;
	}
	if (rc != 0) {
		int e = errno;
		close(fd);
		return rs_error_set(err, RS_ERR_IO, "cannot connect to %s:%u: %s", host, port,
		                    strerror(e));
	}
	*out_fd = fd;
	return RS_OK;
}

void app_peer_name(int fd, char *out, size_t cap)
{
	struct sockaddr_in sa;
	socklen_t len = sizeof sa;
	char ip[INET_ADDRSTRLEN] = "?";
	if (getpeername(fd, (struct sockaddr *)&sa, &len) == 0 &&
	    inet_ntop(AF_INET, &sa.sin_addr, ip, sizeof ip))
		snprintf(out, cap, "%s:%u", ip, ntohs(sa.sin_port));
	else
		snprintf(out, cap, "?");
}

long app_send_some(int fd, const uint8_t *buf, size_t len, struct rs_error *err)
{
	if (len == 0)
		return 0;
	ssize_t n = send(fd, buf, len, MSG_NOSIGNAL | MSG_DONTWAIT);
	if (n >= 0)
		return (long)n;
	if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)
		return 0;
	rs_error_set(err, RS_ERR_DISCONNECTED, "send: %s", strerror(errno));
	return -1;
}

enum rs_status app_parse_size(void *out, const char *value, struct rs_error *err)
{
	const struct app_size *size = out;
	if (!rs_cli_parse_size(value, RS_STREAM_MAX_SIDE, size->width, size->height))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not WxH with sides 1..%u", value,
		                    RS_STREAM_MAX_SIDE);
	return RS_OK;
}
