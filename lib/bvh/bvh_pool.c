/* The SAH builder's worker threads: started once per build, then handed one parallel loop
 * at a time (jobs taken from a shared counter, the caller's thread working too). A build
 * runs a handful of loops, so one start per build instead of one per loop. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

#include "bvh_internal.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define CPU_RELAX() _mm_pause()
#else
#define CPU_RELAX() ((void)0)
#endif

/* How long a thread polls before it sleeps, in polls (a few tens of microseconds): the
 * upper nodes of a build run loops back to back, each a fraction of a millisecond, and a
 * sleeping thread must first be woken and then scheduled. */
#define SPIN_POLLS 4096

struct rs_bvh__pool {
	pthread_mutex_t lock;
	pthread_cond_t wake, done;
	pthread_t *ids;
	uint32_t started; /* helper threads running (the caller is worker 0) */
	/* The loop in progress; generation counts loops so a sleeping worker sees a new one. */
	rs_bvh__job_fn fn;
	void *ctx;
	uint32_t jobs;
	uint64_t generation;
	/* A copy of generation, polled without the lock by helpers about to sleep. */
	_Atomic uint64_t published;
	/* Polls before sleeping: SPIN_POLLS, or 0 with more threads than online cores (a
	 * polling thread would hold a core that a thread with work is waiting for: Cow17 on
	 * four threads of two cores measured 1.24-1.33x Embree's time polling, 1.13-1.18x
	 * not). */
	int spin;
	/* The next job and its loop's generation (high 32 bits) in one word: a helper that
	 * woke late for a loop already over cannot take a job of the next one. */
	_Atomic uint64_t ticket;
	atomic_uint completed; /* jobs of the current loop finished */
	/* Work a helper does between loops (rs_bvh__pool_idle()): idle(idle_ctx, worker) is
	 * called until it returns 0 or a loop is published; pokes counts
	 * rs_bvh__pool_poke() calls, so a helper that found nothing sleeps until the next.
	 * idling: helpers that took idle and may still call it (idle_done: it fell to 0). */
	rs_bvh__idle_fn idle;
	void *idle_ctx;
	uint32_t idling;
	pthread_cond_t idle_done;
	_Atomic uint64_t pokes;
	int quit;
};

struct worker_arg {
	struct rs_bvh__pool *pool;
	uint32_t worker;
};

/* Jobs of loop `gen` until none is left. The caller waits for the jobs to be finished, not
 * for every helper to have looked: on a loaded machine a helper may not run for a while,
 * and a loop it never joined no longer waits for it. */
static void run_jobs(struct rs_bvh__pool *p, rs_bvh__job_fn fn, void *ctx, uint32_t jobs,
                     uint64_t gen, uint32_t worker)
{
	uint64_t t = atomic_load_explicit(&p->ticket, memory_order_acquire);
	for (;;) {
		if (t >> 32 != (gen & 0xffffffffu) || (uint32_t)t >= jobs)
			return;
		if (!atomic_compare_exchange_weak_explicit(
		        &p->ticket, &t, t + 1, memory_order_acq_rel, memory_order_acquire))
			continue;
		fn(ctx, (uint32_t)t, worker);
		if (atomic_fetch_add_explicit(&p->completed, 1, memory_order_acq_rel) + 1 == jobs) {
			pthread_mutex_lock(&p->lock);
			pthread_cond_signal(&p->done);
			pthread_mutex_unlock(&p->lock);
		}
		t = atomic_load_explicit(&p->ticket, memory_order_acquire);
	}
}

static void *worker_main(void *arg)
{
	struct worker_arg *a = arg;
	struct rs_bvh__pool *p = a->pool;
	uint64_t seen = 0, poked = 0;
	pthread_mutex_lock(&p->lock);
	for (;;) {
		while (!p->quit && p->generation == seen &&
		       atomic_load_explicit(&p->pokes, memory_order_relaxed) == poked)
			pthread_cond_wait(&p->wake, &p->lock);
		if (p->quit)
			break;
		int loop = p->generation != seen;
		seen = p->generation;
		poked = atomic_load_explicit(&p->pokes, memory_order_relaxed);
		rs_bvh__job_fn fn = p->fn;
		void *ctx = p->ctx;
		uint32_t jobs = p->jobs;
		rs_bvh__idle_fn idle = p->idle;
		void *idle_ctx = p->idle_ctx;
		p->idling += idle != NULL;
		pthread_mutex_unlock(&p->lock);
		if (loop)
			run_jobs(p, fn, ctx, jobs, seen, a->worker);
		if (idle) {
			/* Between loops: a loop published meanwhile comes first (checked between
			 * calls). */
			while (atomic_load_explicit(&p->published, memory_order_acquire) == seen &&
			       idle(idle_ctx, a->worker))
				;
			pthread_mutex_lock(&p->lock);
			if (--p->idling == 0)
				pthread_cond_broadcast(&p->idle_done);
			pthread_mutex_unlock(&p->lock);
		}
		for (int k = 0; k < p->spin &&
		                atomic_load_explicit(&p->published, memory_order_relaxed) == seen &&
		                atomic_load_explicit(&p->pokes, memory_order_relaxed) == poked;
		     k++)
			CPU_RELAX();
		pthread_mutex_lock(&p->lock);
	}
	pthread_mutex_unlock(&p->lock);
	free(a);
	return NULL;
}

struct rs_bvh__pool *rs_bvh__pool_start(uint32_t threads)
{
	struct rs_bvh__pool *p = calloc(1, sizeof *p);
	if (!p)
		return NULL;
	p->ids = calloc(threads, sizeof *p->ids);
	if (!p->ids || pthread_mutex_init(&p->lock, NULL) != 0) {
		free(p->ids);
		free(p);
		return NULL;
	}
	pthread_cond_init(&p->wake, NULL);
	pthread_cond_init(&p->done, NULL);
	pthread_cond_init(&p->idle_done, NULL);
	atomic_init(&p->ticket, 0);
	atomic_init(&p->completed, 0);
	atomic_init(&p->published, 0);
	atomic_init(&p->pokes, 0);
	long cores = sysconf(_SC_NPROCESSORS_ONLN);
	p->spin = cores > 0 && threads <= (uint32_t)cores ? SPIN_POLLS : 0;
	/* A helper that cannot be started only means fewer hands: the work is the same. */
	for (uint32_t t = 1; t < threads; t++) {
		struct worker_arg *a = malloc(sizeof *a);
		if (!a)
			break;
		*a = (struct worker_arg){p, t};
		if (pthread_create(&p->ids[p->started], NULL, worker_main, a) != 0) {
			free(a);
			break;
		}
		p->started++;
	}
	return p;
}

uint32_t rs_bvh__pool_polls(const struct rs_bvh__pool *p)
{
	return p ? (uint32_t)p->spin : 0;
}

void rs_bvh__pool_relax(void)
{
	CPU_RELAX();
}

uint32_t rs_bvh__pool_workers(const struct rs_bvh__pool *p)
{
	return p ? p->started + 1 : 1;
}

void rs_bvh__pool_run(struct rs_bvh__pool *p, uint32_t jobs, rs_bvh__job_fn fn, void *ctx)
{
	if (!p || p->started == 0 || jobs <= 1) {
		for (uint32_t j = 0; j < jobs; j++)
			fn(ctx, j, 0);
		return;
	}
	pthread_mutex_lock(&p->lock);
	p->fn = fn;
	p->ctx = ctx;
	p->jobs = jobs;
	uint64_t gen = ++p->generation;
	atomic_store(&p->completed, 0);
	atomic_store(&p->ticket, (gen & 0xffffffffu) << 32);
	atomic_store(&p->published, gen);
	pthread_cond_broadcast(&p->wake);
	pthread_mutex_unlock(&p->lock);
	run_jobs(p, fn, ctx, jobs, gen, 0);
	for (int k = 0; k < p->spin && atomic_load(&p->completed) < jobs; k++)
		CPU_RELAX();
	pthread_mutex_lock(&p->lock);
	while (atomic_load(&p->completed) < jobs)
		pthread_cond_wait(&p->done, &p->lock);
	pthread_mutex_unlock(&p->lock);
}

void rs_bvh__pool_idle(struct rs_bvh__pool *p, rs_bvh__idle_fn idle, void *ctx)
{
	if (!p)
		return;
	pthread_mutex_lock(&p->lock);
	p->idle = idle;
	p->idle_ctx = ctx;
	/* Cleared: no helper calls the old one any more once this returns. */
	while (!idle && p->idling > 0)
		pthread_cond_wait(&p->idle_done, &p->lock);
	pthread_mutex_unlock(&p->lock);
}

void rs_bvh__pool_poke(struct rs_bvh__pool *p)
{
	if (!p || p->started == 0)
		return;
	pthread_mutex_lock(&p->lock);
	atomic_fetch_add_explicit(&p->pokes, 1, memory_order_relaxed);
	pthread_cond_broadcast(&p->wake);
	pthread_mutex_unlock(&p->lock);
}

void rs_bvh__pool_stop(struct rs_bvh__pool *p)
{
	if (!p)
		return;
	pthread_mutex_lock(&p->lock);
	p->quit = 1;
	/* Polling helpers stop polling now, not after SPIN_POLLS. */
	atomic_store(&p->published, p->generation + 1);
	pthread_cond_broadcast(&p->wake);
	pthread_mutex_unlock(&p->lock);
	for (uint32_t t = 0; t < p->started; t++)
		pthread_join(p->ids[t], NULL);
	pthread_cond_destroy(&p->wake);
	pthread_cond_destroy(&p->done);
	pthread_cond_destroy(&p->idle_done);
	pthread_mutex_destroy(&p->lock);
	free(p->ids);
	free(p);
}
