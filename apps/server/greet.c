/* Admission: connections that have not said HELLO wait in a small pool of their own
 * (SERVER_MAX_GREETING slots, SERVER_GREETING_PER_ADDRESS per address), so idle or slow
 * connections never take the slots of viewers. When the pool is full the oldest greeting
 * connection of the newcomer's address gives way (or, when that address has none there,
 * the oldest of the busiest address): a flood from one address only pushes out its own
 * connections, and a viewer that says HELLO promptly always gets in. */
#include <stdio.h>
#include <stdlib.h>

#include "server.h"

static struct viewer *oldest_greeting(struct server *s, uint32_t addr, int any_addr)
{
	struct viewer *old = NULL;
	for (uint32_t i = 0; i < SERVER_SLOTS; ++i) {
		struct viewer *v = &s->viewers[i];
		if (!v->active || v->hello_done || (!any_addr && v->addr != addr))
			continue;
		if (!old || v->connected_s < old->connected_s)
			old = v;
	}
	return old;
}

static uint32_t greeting_count(const struct server *s, uint32_t addr, int any_addr,
                               uint32_t *busiest)
{
	uint32_t n = 0, best = 0;
	for (uint32_t i = 0; i < SERVER_SLOTS; ++i) {
		const struct viewer *v = &s->viewers[i];
		if (!v->active || v->hello_done)
			continue;
		if (any_addr || v->addr == addr)
			++n;
		if (busiest) { /* the address with the most greeting connections */
			uint32_t m = greeting_count(s, v->addr, 0, NULL);
			if (m > best) {
				best = m;
				*busiest = v->addr;
			}
		}
	}
	return n;
}

static void evict(struct server *s, struct viewer *v, const char *what)
{
	char why[128];
	snprintf(why, sizeof why, "timeout: no HELLO yet and %s", what);
	server_viewer_close(s, v, RS_STREAM_BYE_TIMEOUT, why);
}

struct viewer *server_greeting_slot(struct server *s, uint32_t addr, double now)
{
	(void)now;
	if (greeting_count(s, addr, 0, NULL) >= SERVER_GREETING_PER_ADDRESS)
		evict(s, oldest_greeting(s, addr, 0),
		      "a newer connection from this address needs the slot");
	uint32_t busiest = addr;
	if (greeting_count(s, addr, 1, &busiest) >= SERVER_MAX_GREETING) {
		struct viewer *v = oldest_greeting(s, addr, 0);
		evict(s, v ? v : oldest_greeting(s, busiest, 0),
		      "the pool of connections waiting for HELLO is full");
	}
	/* a free slot: the pool is bounded above, so one exists unless render threads still
	 * hold a slot that just closed (`busy`) */
	struct viewer *free_slot = NULL;
	pthread_mutex_lock(&s->lock);
	for (uint32_t i = 0; i < SERVER_SLOTS && !free_slot; ++i)
		if (!s->viewers[i].active && !s->viewers[i].busy)
			free_slot = &s->viewers[i];
	pthread_mutex_unlock(&s->lock);
	return free_slot;
}

int server_viewer_promote(struct server *s, struct viewer *v)
{
	uint32_t viewers = 0;
	for (uint32_t i = 0; i < SERVER_SLOTS; ++i)
		viewers += s->viewers[i].active && s->viewers[i].hello_done;
	if (viewers >= s->o.max_viewers) {
		char why[64];
		snprintf(why, sizeof why, "too many viewers (%u)", viewers);
		server_viewer_close(s, v, RS_STREAM_BYE_OVERLOAD, why);
		return -1;
	}
	/* frame buffers only for viewers: a greeting connection costs no frame memory */
	if (!v->pending.data)
		v->pending.data = malloc(s->frame_cap);
	if (!v->inflight.data)
		v->inflight.data = malloc(s->frame_cap);
	if (!v->pending.data || !v->inflight.data) {
		server_viewer_close(s, v, RS_STREAM_BYE_OVERLOAD, "server out of memory");
		return -1;
	}
	return 0;
}
