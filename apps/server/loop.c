/* The poll loop: accepts viewers, sends frames and control messages without ever blocking
 * (a slow viewer only fills its own queue: one frame on the wire, one pending), through the
 * emulated link when one is set, enforces the read timeout (slow drip, no HELLO) and sends
 * each viewer a STATS message a second. */
#define _GNU_SOURCE
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <linux/sockios.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "app_net.h"
#include "server.h"

extern volatile sig_atomic_t server_signal;

/* Small socket send buffers keep frames in our queue, where stale ones can be dropped,
 * instead of in the kernel, where they would only add latency. */
#define SERVER_SNDBUF (128 * 1024)

static void accept_all(struct server *s, int lfd, double now)
{
	for (;;) {
		struct sockaddr_in sa;
		socklen_t sa_len = sizeof sa;
		int fd =
		    accept4(lfd, (struct sockaddr *)&sa, &sa_len, SOCK_NONBLOCK | SOCK_CLOEXEC);
		if (fd < 0)
			return;
		char peer[64];
		app_peer_name(fd, peer, sizeof peer);
		uint32_t addr = sa.sin_addr.s_addr;
		struct viewer *v = server_greeting_slot(s, addr, now);
		if (!v) { /* only while render threads still hold every free slot */
			close(fd);
			server_log(s, "refused %s: no free connection slot", peer);
			continue;
		}
		app_socket_setup(fd, SERVER_SNDBUF);
		pthread_mutex_lock(&s->lock);
		struct outframe pend = v->pending, infl = v->inflight;
		pend.full = infl.full = 0;
		float *acc = v->refine_acc; /* kept, like the frame buffers; refill restarts */
		*v = (struct viewer){.active = 1,
		                     .fd = fd,
		                     .addr = addr,
		                     .id = ++s->next_viewer_id,
		                     .connected_s = now,
		                     .last_stats_s = now,
		                     .pending = pend,
		                     .inflight = infl,
		                     .refine_acc = acc};
		snprintf(v->peer, sizeof v->peer, "%s", peer);
		app_pace_init(&v->pace, s->o.target_fps);
		rs_stream_parser_init(&v->parser, v->inbuf, sizeof v->inbuf);
		struct rs_stream_link_desc ld = {.rate_bits_per_s = s->o.link_mbps * 1e6,
		                                 .latency_s = s->o.link_latency_ms * 1e-3};
		rs_stream_link_init(&v->link, &ld, NULL);
		pthread_mutex_unlock(&s->lock);
		server_log(s, "viewer %u connected from %s", v->id, peer);
	}
}

/* Whether the next frame may go to the socket now. Frames must not wait in kernel buffers,
 * where they can no longer be dropped for newer ones: a new frame starts only once the
 * previous one has left this host (no unsent bytes), and, for a viewer that acknowledges
 * frames, once it has acknowledged every frame sent (one frame on the way at a time). */
static int frame_may_start(struct viewer *v, double *wait_s)
{
	/* the viewer's STATS wakes us; meanwhile the render threads keep the pending frame
	 * fresh (pick() replaces one older than --stale-ms when a newer pose is there) */
	if (v->acks && (uint32_t)v->frames_sent != v->reported.frames)
		return 0;
	int unsent = 0;
	if (ioctl(v->fd, SIOCOUTQNSD, &unsent) == 0 && unsent > 0) {
		if (*wait_s > 0.01)
			*wait_s = 0.01; /* POLLOUT would fire at once: look again shortly */
		return 0;
	}
	return 1;
}

/* Send what the link and socket take now. Returns 1 when it wants POLLOUT, 0 when it
 * is waiting for time (*wait_s) or has nothing, -1 when the viewer was dropped. */
static int flush(struct server *s, struct viewer *v, double now, double *wait_s)
{
	for (;;) {
		int mid_frame = v->inflight.full && v->inflight.off > 0;
		if (!v->sending_ctl && !mid_frame) {
			if (v->ctl_len > v->ctl_off) {
				v->sending_ctl = 1;
			} else if (!v->inflight.full && frame_may_start(v, wait_s)) {
				pthread_mutex_lock(&s->lock);
				if (v->pending.full && v->pending.ready_s <= now) {
					struct outframe t = v->inflight;
					v->inflight = v->pending;
					v->pending = t;
					v->pending.full = 0;
					pthread_cond_signal(&s->work); /* room for the next frame */
				} else if (v->pending.full && v->pending.ready_s - now < *wait_s) {
					*wait_s = v->pending.ready_s - now; /* link latency */
				}
				pthread_mutex_unlock(&s->lock);
			}
		}
		uint8_t *buf;
		size_t left;
		if (v->sending_ctl) {
			buf = v->ctl + v->ctl_off;
			left = v->ctl_len - v->ctl_off;
		} else if (v->inflight.full) {
			buf = v->inflight.data + v->inflight.off;
			left = v->inflight.len - v->inflight.off;
		} else {
			return 0;
		}
		size_t allow = rs_stream_link_allow(&v->link, now, left);
		if (allow == 0) {
			double w = rs_stream_link_wait_s(&v->link, now, left);
			if (w < *wait_s)
				*wait_s = w;
			return 0;
		}
		struct rs_error err = {0};
		long n = app_send_some(v->fd, buf, allow, &err);
		if (n < 0) {
			/* a viewer that said BYE and closed: log that, not the failed send */
			server_viewer_read(s, v, now);
			if (!v->active)
				return -1;
			char why[RS_ERROR_MESSAGE_MAX + 32];
			snprintf(why, sizeof why, "connection lost: %s", err.message);
			server_viewer_close(s, v, RS_STREAM_BYE_PROTOCOL, why);
			return -1;
		}
		rs_stream_link_spend(&v->link, (size_t)n);
		v->bytes_sent += (uint64_t)n;
		if (v->sending_ctl) {
			v->ctl_off += (size_t)n;
			if (v->ctl_off == v->ctl_len) {
				v->ctl_off = v->ctl_len = 0;
				v->sending_ctl = 0;
			}
		} else {
			v->inflight.off += (size_t)n;
			if (v->inflight.off == v->inflight.len) {
				v->inflight.full = 0;
				v->inflight.off = 0;
				++v->frames_sent;
			}
		}
		if ((size_t)n < allow)
			return 1; /* the socket is full */
	}
}

static void housekeeping(struct server *s, struct viewer *v, double now)
{
	char why[96];
	if (!v->hello_done && now - v->connected_s > s->o.read_timeout_s) {
		snprintf(why, sizeof why, "timeout: no HELLO within %.1f s", s->o.read_timeout_s);
		server_viewer_close(s, v, RS_STREAM_BYE_TIMEOUT, why);
		return;
	}
	if (v->msg_start_s > 0 && now - v->msg_start_s > s->o.read_timeout_s) {
		snprintf(why, sizeof why,
		         "timeout: message incomplete after %.1f s (%zu bytes, slow drip)",
		         s->o.read_timeout_s, v->parser.len);
		server_viewer_close(s, v, RS_STREAM_BYE_TIMEOUT, why);
		return;
	}
	if (v->hello_done && now - v->last_stats_s >= 1.0) {
		struct rs_stream_msg m = {.type = RS_STREAM_STATS};
		double dt = now - v->connected_s;
		pthread_mutex_lock(&s->lock);
		m.u.stats.frames = (uint32_t)v->frames_sent;
		m.u.stats.dropped = (uint32_t)v->frames_dropped;
		m.u.stats.bytes = v->bytes_sent;
		m.u.stats.fps = dt > 0 ? (float)(v->frames_rendered / dt) : 0.0f;
		m.u.stats.link_mbps = dt > 0 ? (float)(v->bytes_sent * 8.0 / dt / 1e6) : 0.0f;
		pthread_mutex_unlock(&s->lock);
		server_viewer_queue(v, &m);
		v->last_stats_s = now;
	}
}

int server_run(struct server *s, int lfd)
{
	struct pollfd pfd[SERVER_SLOTS + 2];
	int map[SERVER_SLOTS + 2];
	while (!server_signal) {
		double now = server_now_s();
		if (s->o.duration_s > 0 && now - s->started_s >= s->o.duration_s)
			break;
		double wait_s = 0.1;
		nfds_t n = 0;
		pfd[n++] = (struct pollfd){.fd = lfd, .events = POLLIN};
		pfd[n++] = (struct pollfd){.fd = s->wake[0], .events = POLLIN};
		for (int i = 0; i < SERVER_SLOTS; ++i) {
			struct viewer *v = &s->viewers[i];
			if (!v->active)
				continue;
			int want_out = flush(s, v, now, &wait_s);
			if (want_out < 0)
				continue;
			map[n] = i;
			pfd[n++] = (struct pollfd){
			    .fd = v->fd, .events = (short)(POLLIN | (want_out ? POLLOUT : 0))};
		}
		int timeout_ms = (int)(wait_s * 1000.0) + 1;
		if (poll(pfd, n, timeout_ms) < 0 && errno != EINTR) {
			server_log(s, "poll failed: %s", strerror(errno));
			return 1;
		}
		now = server_now_s();
		if (pfd[1].revents & POLLIN) {
			char drain[256];
			while (read(s->wake[0], drain, sizeof drain) > 0) {
			}
		}
		if (pfd[0].revents & POLLIN)
			accept_all(s, lfd, now);
		for (nfds_t k = 2; k < n; ++k) {
			struct viewer *v = &s->viewers[map[k]];
			if (v->active && (pfd[k].revents & (POLLIN | POLLHUP | POLLERR)))
				server_viewer_read(s, v, now);
			if (v->active)
				housekeeping(s, v, now);
		}
	}
	for (int i = 0; i < SERVER_SLOTS; ++i)
		if (s->viewers[i].active)
			server_viewer_close(s, &s->viewers[i], RS_STREAM_BYE_SHUTDOWN,
			                    "server shutting down");
	return 0;
}
