/* Shared by raystream-server and raystream-viewer: sockets and small helpers. */
#ifndef RS_APP_NET_H
#define RS_APP_NET_H

#include <stddef.h>
#include <stdint.h>

#include <cjson/cJSON.h>

#include "raystream/rs_status.h"

/* "HOST:PORT" (IPv4 dotted quad or "localhost"; port 0..65535) into host/port. */
enum rs_status app_parse_hostport(const char *text, char *host, size_t host_cap, uint16_t *port,
                                  struct rs_error *err);

/* A non-blocking listening socket on host:port (port 0: any free port); *out_port gets the
 * bound port. */
enum rs_status app_listen(const char *host, uint16_t port, int *out_fd, uint16_t *out_port,
                          struct rs_error *err);

/* A blocking connect with a timeout; the socket is left non-blocking with TCP_NODELAY. */
enum rs_status app_connect(const char *host, uint16_t port, int timeout_ms, int *out_fd,
                           struct rs_error *err);

/* Non-blocking, close-on-exec, TCP_NODELAY and, when sndbuf > 0, that send buffer. */
void app_socket_setup(int fd, int sndbuf);

/* "a.b.c.d:port" of the peer (or "?"). */
void app_peer_name(int fd, char *out, size_t cap);

/* Send as much of buf as the socket takes now (MSG_NOSIGNAL). Returns bytes sent (>= 0),
 * or -1 with a reason in err for a dead connection. */
long app_send_some(int fd, const uint8_t *buf, size_t len, struct rs_error *err);

/* --size WxH for the apps: sides 1..RS_STREAM_MAX_SIDE (what a FRAME can carry); an
 * RS_CLI_CALL option whose `out` is a struct app_size. */
struct app_size {
	uint32_t *width, *height;
};
enum rs_status app_parse_size(void *out, const char *value, struct rs_error *err);

/* Write `doc` to `path` (a temporary file, then a rename). */
enum rs_status app_write_json(const char *path, const cJSON *doc, struct rs_error *err);

#endif
