/* What viewers send: parsing, HELLO checks, latest-wins poses, and closing a connection
 * with a BYE and a logged reason. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "app_net.h"
#include "server.h"

/* Queue a control message (whole messages only; the buffer is ample for the few we send). */
int server_viewer_queue(struct viewer *v, const struct rs_stream_msg *m)
{
	size_t n = 0;
	if (rs_stream_encode(m, v->ctl + v->ctl_len, sizeof v->ctl - v->ctl_len, &n, NULL) != RS_OK)
		return -1;
	v->ctl_len += n;
	return 0;
}

static void queue_bye(struct viewer *v, uint32_t reason, const char *text)
{
	struct rs_stream_msg m = {.type = RS_STREAM_BYE};
	m.u.bye.reason = reason;
	snprintf(m.u.bye.text, sizeof m.u.bye.text, "%s", text);
	for (char *c = m.u.bye.text; *c; ++c) /* reasons quote peer data: keep them printable */
		if (*c < 0x20 || *c > 0x7e)
			*c = '?';
	server_viewer_queue(v, &m);
}

static void drop_viewer(struct server *s, struct viewer *v, const char *why)
{
	pthread_mutex_lock(&s->lock);
	server_log(s,
	           "viewer %u (%s) disconnected: %s [frames sent %llu, dropped %llu, poses %llu]",
	           v->id, v->peer, why, (unsigned long long)v->frames_sent,
	           (unsigned long long)v->frames_dropped, (unsigned long long)v->poses);
	close(v->fd);
	v->active = 0;
	v->fd = -1;
	v->pending.full = 0;
	++s->disconnects;
	pthread_mutex_unlock(&s->lock);
}

/* Best effort: a BYE goes out when the socket takes it now and no frame is half sent;
 * then the connection closes either way. */
void server_viewer_close(struct server *s, struct viewer *v, uint32_t reason, const char *why)
{
	if (!v->inflight.full || v->inflight.off == 0) {
		if (v->sending_ctl) /* finish whole control messages first */
			app_send_some(v->fd, v->ctl + v->ctl_off, v->ctl_len - v->ctl_off, NULL);
		v->ctl_len = v->ctl_off = 0;
		queue_bye(v, reason, why);
		app_send_some(v->fd, v->ctl, v->ctl_len, NULL);
	}
	drop_viewer(s, v, why);
}

static void on_hello(struct server *s, struct viewer *v, const struct rs_stream_hello *h)
{
	char why[RS_STREAM_MAX_TEXT + 1];
	if (strcmp(h->token, s->o.token ? s->o.token : "") != 0) {
		server_viewer_close(s, v, RS_STREAM_BYE_TOKEN, "wrong token");
		return;
	}
	if ((h->scene[0] && strcmp(h->scene, s->o.scene) != 0) || h->width != s->o.width ||
	    h->height != s->o.height) {
		snprintf(why, sizeof why, "this server renders scene %s at %ux%u, not %s at %ux%u",
		         s->o.scene, s->o.width, s->o.height, h->scene[0] ? h->scene : "(any)",
		         h->width, h->height);
		server_viewer_close(s, v, RS_STREAM_BYE_SCENE, why);
		return;
	}
	if (server_viewer_promote(s, v) != 0)
		return;
	pthread_mutex_lock(&s->lock); /* render threads read both */
	v->quality = h->quality ? h->quality : s->o.quality;
	v->hello_done = 1;
	pthread_mutex_unlock(&s->lock);
	struct rs_stream_msg m = {.type = RS_STREAM_WELCOME};
	m.u.welcome = (struct rs_stream_welcome){.viewer_id = v->id,
	                                         .width = (uint16_t)s->o.width,
	                                         .height = (uint16_t)s->o.height,
	                                         .quality = (uint8_t)v->quality,
	                                         .encoding = s->o.raw ? RS_STREAM_ENC_RGBA8
	                                                              : RS_STREAM_ENC_JPEG};
	server_viewer_queue(v, &m);
	server_log(s, "viewer %u (%s) joined at quality %d", v->id, v->peer, v->quality);
}

void server_pose_camera(const struct server *s, const struct rs_stream_pose *p,
                        struct rs_camera *cam)
{
	*cam = (struct rs_camera){
	    .fov_y_deg = p->fov_y_deg, .width = s->o.width, .height = s->o.height};
	memcpy(cam->eye, p->eye, sizeof cam->eye);
	memcpy(cam->target, p->target, sizeof cam->target);
	memcpy(cam->up, p->up, sizeof cam->up);
	memcpy(cam->shift, p->shift, sizeof cam->shift);
}

/* A camera the renderer cannot use (eye on its target, up along the view) gets an answer
 * at once: a BYE naming the problem, not a silently missing frame. */
static int check_pose(struct server *s, struct viewer *v, const struct rs_stream_pose *p)
{
	struct rs_camera cam;
	server_pose_camera(s, p, &cam);
	struct rs_error err = {0};
	if (rs_camera_check(&cam, &err) != RS_OK) {
		char why[RS_ERROR_MESSAGE_MAX + 32];
		snprintf(why, sizeof why, "POSE %u: %s", p->pose_id, err.message);
		server_viewer_close(s, v, RS_STREAM_BYE_CAMERA, why);
		return -1;
	}
	v->acks = (p->flags & RS_STREAM_POSE_ACKS) != 0;
	v->refine = (p->flags & RS_STREAM_POSE_REFINE) != 0;
	return 0;
}

/* Handle one parsed message; returns 0 to keep the connection. */
static int on_message(struct server *s, struct viewer *v, const struct rs_stream_msg *m)
{
	char why[RS_STREAM_MAX_TEXT + 64];
	if (!v->hello_done && m->type != RS_STREAM_HELLO && m->type != RS_STREAM_BYE) {
		snprintf(why, sizeof why, "protocol error: %s before HELLO",
		         rs_stream_type_name(m->type));
		server_viewer_close(s, v, RS_STREAM_BYE_PROTOCOL, why);
		return -1;
	}
	switch (m->type) {
	case RS_STREAM_HELLO:
		if (v->hello_done) {
			server_viewer_close(s, v, RS_STREAM_BYE_PROTOCOL,
			                    "protocol error: second HELLO");
			return -1;
		}
		on_hello(s, v, &m->u.hello);
		return v->active ? 0 : -1;
	case RS_STREAM_POSE:
		if (check_pose(s, v, &m->u.pose) != 0)
			return -1;
		pthread_mutex_lock(&s->lock);
		if (v->pose_new)
			++v->poses_replaced; /* latest wins */
		v->pose = m->u.pose;
		v->pose_new = 1;
		++v->poses;
		pthread_cond_signal(&s->work);
		pthread_mutex_unlock(&s->lock);
		return 0;
	case RS_STREAM_STATS:
		v->reported = m->u.stats;
		return 0;
	case RS_STREAM_BYE:
		snprintf(why, sizeof why, "viewer said bye (%u: %s)", m->u.bye.reason,
		         m->u.bye.text);
		drop_viewer(s, v, why);
		return -1;
	default:
		snprintf(why, sizeof why, "protocol error: %s from a viewer",
		         rs_stream_type_name(m->type));
		server_viewer_close(s, v, RS_STREAM_BYE_PROTOCOL, why);
		return -1;
	}
}

/* Read what is there (bounded per round, so a flooding viewer cannot starve others). */
void server_viewer_read(struct server *s, struct viewer *v, double now)
{
	uint8_t buf[16384];
	for (int round = 0; round < 4 && v->active; ++round) {
		ssize_t n = recv(v->fd, buf, sizeof buf, MSG_DONTWAIT);
		if (n == 0) {
			char why[96];
			if (v->parser.len)
				snprintf(why, sizeof why,
				         "connection closed mid-message (%zu bytes pending)",
				         v->parser.len);
			else
				snprintf(why, sizeof why, "connection closed without BYE");
			drop_viewer(s, v, why);
			return;
		}
		if (n < 0) {
			if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)
				return;
			char why[96];
			snprintf(why, sizeof why, "receive failed: %s", strerror(errno));
			drop_viewer(s, v, why);
			return;
		}
		const uint8_t *d = buf;
		size_t left = (size_t)n;
		for (;;) {
			struct rs_stream_msg m;
			struct rs_error err = {0};
			enum rs_status st = rs_stream_parser_feed(&v->parser, &d, &left, &m, &err);
			if (st == RS_END)
				break;
			if (st != RS_OK) {
				char why[RS_ERROR_MESSAGE_MAX + 32];
				snprintf(why, sizeof why, "protocol error: %s", err.message);
				server_viewer_close(s, v, RS_STREAM_BYE_PROTOCOL, why);
				return;
			}
			if (on_message(s, v, &m) != 0)
				return;
		}
		/* garbage between messages is a protocol error too, not just a counter */
		if (v->parser.faults.garbage_bytes > 0) {
			char why[96];
			snprintf(why, sizeof why, "protocol error: %llu bytes that are no message",
			         (unsigned long long)v->parser.faults.garbage_bytes);
			server_viewer_close(s, v, RS_STREAM_BYE_PROTOCOL, why);
			return;
		}
		/* a message that started arriving must complete within the read timeout */
		if (v->parser.len == 0)
			v->msg_start_s = 0;
		else if (v->msg_start_s == 0)
			v->msg_start_s = now;
		if ((size_t)n < sizeof buf)
			return;
	}
}
