/* The viewer's side of the stream protocol: HELLO/WELCOME, poses out (the newest unsent
 * one replaces an older one: latest wins on this side too), frames in. */
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "app_net.h"
#include "viewer.h"

static int send_all_blocking(int fd, const uint8_t *b, size_t n, double deadline_s)
{
	while (n > 0) {
		struct rs_error err = {0};
		long k = app_send_some(fd, b, n, &err);
		if (k < 0)
			return -1;
		b += k;
		n -= (size_t)k;
		if (n > 0) {
			if (viewer_now_s() > deadline_s)
				return -1;
			struct pollfd p = {.fd = fd, .events = POLLOUT};
			poll(&p, 1, 10);
		}
	}
	return 0;
}

int viewer_connect(struct viewer *v)
{
	struct rs_error err = {0};
	char host[64];
	uint16_t port = 0;
	struct viewer_link *l = &v->link;
	if (app_parse_hostport(v->o.server, host, sizeof host, &port, &err) != RS_OK ||
	    app_connect(host, port, 3000, &l->fd, &err) != RS_OK) {
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
		return -1;
	}
	/* the largest frame of this size: raw RGBA8 or the worst-case JPEG */
	size_t raw = (size_t)v->o.width * v->o.height * 4u,
	       jpg = rs_jpeg_bound(v->o.width, v->o.height);
	size_t cap = rs_stream_parser_bound(raw > jpg ? raw : jpg);
	l->inbuf = malloc(cap);
	if (!l->inbuf) {
		fprintf(stderr, "raystream-viewer: out of memory\n");
		return -1;
	}
	rs_stream_parser_init(&l->parser, l->inbuf, cap);
	struct rs_stream_msg m = {.type = RS_STREAM_HELLO};
	m.u.hello.width = (uint16_t)v->o.width;
	m.u.hello.height = (uint16_t)v->o.height;
	m.u.hello.quality = (uint8_t)v->o.quality;
	snprintf(m.u.hello.token, sizeof m.u.hello.token, "%s", v->o.token ? v->o.token : "");
	snprintf(m.u.hello.scene, sizeof m.u.hello.scene, "%s", v->o.scene);
	uint8_t b[RS_STREAM_HEADER_SIZE + RS_STREAM_MAX_CLIENT_PAYLOAD];
	size_t n = 0;
	double deadline = viewer_now_s() + 5.0;
	if (rs_stream_encode(&m, b, sizeof b, &n, &err) != RS_OK ||
	    send_all_blocking(l->fd, b, n, deadline) != 0) {
		fprintf(stderr, "raystream-viewer: cannot send HELLO: %s\n",
		        err.message[0] ? err.message : "connection failed");
		return -1;
	}
	/* the answer: WELCOME, or BYE with the reason */
	while (viewer_now_s() < deadline) {
		struct pollfd p = {.fd = l->fd, .events = POLLIN};
		poll(&p, 1, 50);
		uint8_t in[512];
		ssize_t k = recv(l->fd, in, sizeof in, MSG_DONTWAIT);
		if (k == 0) {
			fprintf(stderr, "raystream-viewer: the server closed the connection\n");
			return -1;
		}
		if (k < 0)
			continue;
		const uint8_t *d = in;
		size_t left = (size_t)k;
		struct rs_stream_msg r;
		enum rs_status st = rs_stream_parser_feed(&l->parser, &d, &left, &r, &err);
		if (st == RS_END)
			continue;
		if (st == RS_OK && r.type == RS_STREAM_WELCOME && r.u.welcome.width == v->o.width &&
		    r.u.welcome.height == v->o.height) {
			l->viewer_id = r.u.welcome.viewer_id;
			if (left) { /* bytes after WELCOME: keep them for the parser */
				const uint8_t *dd = d;
				size_t ll = left;
				struct rs_stream_msg x;
				while (rs_stream_parser_feed(&l->parser, &dd, &ll, &x, NULL) ==
				       RS_OK) {
				}
			}
			return 0;
		}
		if (st == RS_OK && r.type == RS_STREAM_BYE)
			fprintf(stderr, "raystream-viewer: server refused: %s\n", r.u.bye.text);
		else
			fprintf(stderr, "raystream-viewer: unexpected answer to HELLO (%s)\n",
			        st == RS_OK ? rs_stream_type_name(r.type) : err.message);
		return -1;
	}
	fprintf(stderr, "raystream-viewer: no answer to HELLO within 5 s\n");
	return -1;
}

void viewer_send_pose(struct viewer *v, const struct rs_camera *cam, uint32_t flags)
{
	struct viewer_link *l = &v->link;
	if (l->out_off > 0 && l->out_off < l->out_len)
		return; /* half sent: finish it first; the next camera follows */
	struct rs_stream_msg m = {.type = RS_STREAM_POSE};
	struct rs_stream_pose *p = &m.u.pose;
	p->pose_id = v->pose_id;
	p->flags =
	    flags | RS_STREAM_POSE_ACKS | (v->refine_remote.enabled ? RS_STREAM_POSE_REFINE : 0u);
	p->time_us = (uint64_t)(viewer_now_s() * 1e6);
	memcpy(p->eye, cam->eye, sizeof p->eye);
	memcpy(p->target, cam->target, sizeof p->target);
	memcpy(p->up, cam->up, sizeof p->up);
	p->fov_y_deg = cam->fov_y_deg;
	memcpy(p->shift, cam->shift, sizeof p->shift);
	size_t n = 0;
	if (rs_stream_encode(&m, l->out, sizeof l->out, &n, NULL) == RS_OK) {
		l->out_len = n;
		l->out_off = 0;
	}
}

static int handle(struct viewer *v, const struct rs_stream_msg *m)
{
	struct viewer_link *l = &v->link;
	struct rs_error err = {0};
	switch (m->type) {
	case RS_STREAM_FRAME: {
		const struct rs_stream_frame *f = &m->u.frame;
		++l->frames_in;
		/* smaller: the server's --target-fps scale; scaled up here to the window's size */
		if (!f->width || !f->height || f->width > v->o.width || f->height > v->o.height) {
			fprintf(stderr, "raystream-viewer: frame %u is %ux%u, not at most %ux%u\n",
			        f->frame_id, f->width, f->height, v->o.width, v->o.height);
			return -1;
		}
		int full = f->width == v->o.width && f->height == v->o.height;
		uint8_t *to = v->rgba;
		if (!full) {
			uint8_t *b = realloc(v->small, (size_t)f->width * f->height * 4u);
			if (!b) {
				fprintf(stderr, "raystream-viewer: out of memory\n");
				return -1;
			}
			to = v->small = b;
		}
		if (f->encoding == RS_STREAM_ENC_RGBA8)
			memcpy(to, f->data, f->size);
		else if (rs_jpeg_decode(v->jpeg, f->data, f->size, f->width, f->height, to, &err) !=
		         RS_OK) {
			fprintf(stderr, "raystream-viewer: frame %u: %s\n", f->frame_id,
			        err.message);
			return 0; /* a bad frame is skipped, never shown half-decoded */
		}
		if (!full)
			app_pace_resample(to, f->width, f->height, v->rgba, v->o.width,
			                  v->o.height);
		v->remote_scale = (double)f->width / v->o.width;
		if (v->remote_scale < v->remote_scale_min)
			v->remote_scale_min = v->remote_scale;
		v->remote_samples = f->samples ? f->samples : 1u;
		if (v->remote)
			viewer_show(v, f->frame_id, f->pose_id, f->pose_time_us);
		return 0;
	}
	case RS_STREAM_STATS:
		l->server_stats = m->u.stats;
		return 0;
	case RS_STREAM_BYE:
		fprintf(stderr, "raystream-viewer: server said bye: %s\n", m->u.bye.text);
		return -1;
	default:
		fprintf(stderr, "raystream-viewer: unexpected %s from the server\n",
		        rs_stream_type_name(m->type));
		return -1;
	}
}

/* Acknowledge the frames received so far, between whole poses (the server sends the next
 * frame only after it: a stalled viewer finds one old frame waiting, not a backlog).
 * Returns 0, or -1 when the connection is gone. */
static int send_ack(struct viewer_link *l, struct rs_error *err)
{
	int pose_half_sent = l->out_off > 0 && l->out_off < l->out_len;
	if (l->ack_off == l->ack_len && l->frames_acked != l->frames_in && !pose_half_sent) {
		struct rs_stream_msg m = {.type = RS_STREAM_STATS};
		m.u.stats.frames = l->frames_in;
		if (rs_stream_encode(&m, l->ack, sizeof l->ack, &l->ack_len, NULL) != RS_OK)
			return 0;
		l->ack_off = 0;
		l->frames_acked = l->frames_in;
	}
	if (l->ack_off < l->ack_len) {
		long k = app_send_some(l->fd, l->ack + l->ack_off, l->ack_len - l->ack_off, err);
		if (k < 0)
			return -1;
		l->ack_off += (size_t)k;
	}
	return 0;
}

int viewer_pump(struct viewer *v, int timeout_ms)
{
	struct viewer_link *l = &v->link;
	struct rs_error err = {0};
	if (send_ack(l, &err) != 0) {
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
		return -1;
	}
	if (l->out_off < l->out_len && l->ack_off == l->ack_len) {
		long k = app_send_some(l->fd, l->out + l->out_off, l->out_len - l->out_off, &err);
		if (k < 0) {
			fprintf(stderr, "raystream-viewer: %s\n", err.message);
			return -1;
		}
		l->out_off += (size_t)k;
	}
	struct pollfd p = {.fd = l->fd, .events = POLLIN};
	if (poll(&p, 1, timeout_ms) <= 0)
		return 0;
	static uint8_t in[1 << 16];
	for (int round = 0; round < 64; ++round) {
		ssize_t k = recv(l->fd, in, sizeof in, MSG_DONTWAIT);
		if (k == 0) {
			fprintf(stderr, "raystream-viewer: the server closed the connection\n");
			return -1;
		}
		if (k < 0) {
			if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)
				break;
			fprintf(stderr, "raystream-viewer: receive failed: %s\n", strerror(errno));
			return -1;
		}
		l->bytes_in += (uint64_t)k;
		const uint8_t *d = in;
		size_t left = (size_t)k;
		for (;;) {
			struct rs_stream_msg m;
			enum rs_status st = rs_stream_parser_feed(&l->parser, &d, &left, &m, &err);
			if (st == RS_END)
				break;
			if (st != RS_OK) {
				fprintf(stderr, "raystream-viewer: bad data from the server: %s\n",
				        err.message);
				return -1;
			}
			if (handle(v, &m) != 0)
				return -1;
		}
	}
	if (send_ack(l, &err) != 0) { /* at once: the server waits for it */
		fprintf(stderr, "raystream-viewer: %s\n", err.message);
		return -1;
	}
	return 0;
}

void viewer_disconnect(struct viewer *v, const char *why)
{
	struct viewer_link *l = &v->link;
	if (l->fd > 0) {
		struct rs_stream_msg m = {.type = RS_STREAM_BYE};
		snprintf(m.u.bye.text, sizeof m.u.bye.text, "%s", why);
		uint8_t b[RS_STREAM_HEADER_SIZE + 8 + RS_STREAM_MAX_TEXT];
		size_t n = 0;
		/* only at a message boundary, so the BYE is never spliced into a pose */
		if ((l->out_off == 0 || l->out_off == l->out_len) && l->ack_off == l->ack_len &&
		    rs_stream_encode(&m, b, sizeof b, &n, NULL) == RS_OK)
			send_all_blocking(l->fd, b, n, viewer_now_s() + 0.5);
		close(l->fd);
		l->fd = -1;
	}
	free(l->inbuf);
	l->inbuf = NULL;
}
