/*
 * raystream-track --bench: parser throughput (clean and noisy streams) and end-to-end
 * latency through the serial path: simulator sample -> frame -> pty master -> serial
 * source (poll, read, parse) -> pose solver. Timings are printed, never asserted.
 */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "raystream/rs_pose.h"
#include "raystream/rs_track.h"
#include "raystream/rs_serial.h"
#include "track_tool.h"

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static void report(const char *what, double *v, int n)
{
	qsort(v, (size_t)n, sizeof *v, cmp_double);
	printf("%-34s median %7.1f us  p95 %7.1f us  p99 %7.1f us  max %7.1f us  (n=%d)\n", what,
	       v[n / 2] * 1e6, v[(int)(n * 0.95)] * 1e6, v[(int)(n * 0.99)] * 1e6, v[n - 1] * 1e6,
	       n);
}

/* Parse `buf` over and over for about a second; frames per second of parser time. */
static void bench_parser(const char *what, const uint8_t *buf, size_t len, size_t frames_in_buf)
{
	struct rs_proto_parser p;
	rs_proto_parser_init(&p);
	struct rs_marker_sample s;
	uint64_t frames = 0, bytes = 0;
	double t0 = rs_track_now_s(), t;
	do {
		/* A fresh sequence history per pass, so repeats are not rejected as duplicates. */
		rs_proto_parser_reset(&p);
		const uint8_t *d = buf;
		size_t n = len;
		while (rs_proto_parser_feed(&p, &d, &n, &s))
			frames++;
		bytes += len;
		t = rs_track_now_s() - t0;
	} while (t < 1.0);
	printf("%-34s %10.0f frames/s  %7.1f MB/s  (%llu frames, expected %llu)\n", what,
	       (double)frames / t, (double)bytes / t / 1e6, (unsigned long long)frames,
	       (unsigned long long)(frames_in_buf * (bytes / len)));
}

static int parser_benchmarks(void)
{
	enum { FRAMES = 8192 };
	size_t clean_len = (size_t)FRAMES * RS_PROTO_FRAME_SIZE;
	uint8_t *clean = malloc(clean_len), *noisy = malloc(2 * clean_len);
	if (!clean || !noisy) {
		free(clean);
		free(noisy);
		fprintf(stderr, "raystream-track: out of memory\n");
		return 1;
	}
	struct rs_sim_desc d = {.noise_sigma_m = 0.0005};
	struct rs_sim *sim = NULL;
	if (rs_sim_create(&d, &sim, NULL) != RS_OK)
		return 1;
	uint64_t r = 0x9E3779B97F4A7C15ull;
	size_t off = 0;
	for (size_t i = 0; i < FRAMES; i++) {
		struct rs_marker_sample s;
		rs_sim_next(sim, &s, NULL, NULL);
		rs_proto_encode(&s, clean + i * RS_PROTO_FRAME_SIZE, NULL);
		/* Noisy stream: each frame preceded by as many random bytes (50 % garbage). */
		for (size_t k = 0; k < RS_PROTO_FRAME_SIZE; k++) {
			r ^= r << 13, r ^= r >> 7, r ^= r << 17;
			noisy[off++] = (uint8_t)r;
		}
		memcpy(noisy + off, clean + i * RS_PROTO_FRAME_SIZE, RS_PROTO_FRAME_SIZE);
		off += RS_PROTO_FRAME_SIZE;
	}
	rs_sim_destroy(&sim);
	bench_parser("parser, clean stream", clean, clean_len, FRAMES);
	bench_parser("parser, 50% random garbage", noisy, off, FRAMES);
	free(clean);
	free(noisy);
	return 0;
}

static int latency_benchmark(int samples, const struct rs_pose_layout *layout)
{
	struct rs_error err;
	struct rs_serial_pty *pty = NULL;
	struct rs_track_source *src = NULL;
	struct rs_pose_solver *solver = NULL;
	struct rs_sim *sim = NULL;
	double *lat_arrive = calloc((size_t)samples, sizeof(double));
	double *lat_parse = calloc((size_t)samples, sizeof(double));
	double *lat_pose = calloc((size_t)samples, sizeof(double));
	int code = 1, n = 0;
	struct rs_sim_desc sd = {.noise_sigma_m = 0.0005,
	                         .layout = (const double(*)[3])layout->markers};
	if (!lat_arrive || !lat_parse || !lat_pose) {
		fprintf(stderr, "raystream-track: out of memory\n");
		goto out;
	}
	if (rs_serial_pty_create(&pty, &err) != RS_OK ||
	    rs_serial_open(&(struct rs_serial_desc){.path = rs_serial_pty_path(pty)}, &src, &err) !=
	        RS_OK ||
	    rs_pose_solver_create(NULL, layout, &solver, &err) != RS_OK ||
	    rs_sim_create(&sd, &sim, &err) != RS_OK) {
		fprintf(stderr, "raystream-track: bench: %s\n", err.message);
		goto out;
	}
	for (int i = 0; i < samples; i++) {
		struct rs_marker_sample s, got;
		uint8_t frame[RS_PROTO_FRAME_SIZE];
		rs_sim_next(sim, &s, NULL, NULL);
		rs_proto_encode(&s, frame, NULL);
		double t0 = rs_track_now_s();
		if (rs_serial_pty_write(pty, frame, sizeof frame, &err) != RS_OK ||
		    rs_track_source_read(src, &got, 1000, NULL) != RS_OK) {
			fprintf(stderr, "raystream-track: bench: sample %d lost: %s\n", i,
			        rs_track_source_last_error(src));
			goto out;
		}
		double t1 = rs_track_now_s();
		struct rs_pose pose;
		struct rs_pose_quality q;
		rs_pose_solver_update(solver, &got, &pose, &q);
		double t2 = rs_track_now_s();
		lat_arrive[n] = got.host_time_s - t0;
		lat_parse[n] = t1 - t0;
		lat_pose[n] = t2 - t0;
		n++;
	}
	report("pty write -> bytes read (host stamp)", lat_arrive, n);
	report("pty write -> parsed sample", lat_parse, n);
	report("pty write -> solved pose", lat_pose, n);
	code = 0;
out:
	rs_sim_destroy(&sim);
	rs_pose_solver_destroy(&solver);
	rs_track_source_destroy(&src);
	rs_serial_pty_destroy(&pty);
	free(lat_arrive);
	free(lat_parse);
	free(lat_pose);
	return code;
}

/* The paced run: a writer thread plays a device at `rate_hz`, stamping each frame's
 * device time with the host clock at the write; the reader sits in poll() as a real
 * application would, so wake-up latency is included. */
struct writer {
	struct rs_serial_pty *pty;
	int samples;
	double rate_hz;
	int failed;
};

static void *writer_main(void *arg)
{
	struct writer *w = arg;
	double start = rs_track_now_s() + 0.05;
	for (int i = 0; i < w->samples; i++) {
		double due = start + i / w->rate_hz, wait = due - rs_track_now_s();
		if (wait > 0) {
			struct timespec ts = {(time_t)wait,
			                      (long)((wait - (double)(time_t)wait) * 1e9)};
			nanosleep(&ts, NULL);
		}
		struct rs_marker_sample s = {.sequence = (uint32_t)i, .marker_count = 3};
		uint8_t frame[RS_PROTO_FRAME_SIZE];
		s.device_time_us = (uint64_t)(rs_track_now_s() * 1e6);
		rs_proto_encode(&s, frame, NULL);
		/* Bounded: if the reader gave up, a full line must not keep this thread (and
		 * the pthread_join() waiting for it) blocked for ever. */
		if (rs_serial_pty_write_timeout(w->pty, frame, sizeof frame, 3000, NULL, NULL) !=
		    RS_OK) {
			w->failed = 1;
			break;
		}
	}
	return NULL;
}

static int paced_latency(int samples, double rate_hz)
{
	struct rs_error err;
	struct rs_serial_pty *pty = NULL;
	struct rs_track_source *src = NULL;
	double *arrive = calloc((size_t)samples, sizeof(double));
	double *parsed = calloc((size_t)samples, sizeof(double));
	int code = 1, n = 0;
	if (!arrive || !parsed || rs_serial_pty_create(&pty, &err) != RS_OK ||
	    rs_serial_open(&(struct rs_serial_desc){.path = rs_serial_pty_path(pty)}, &src, &err) !=
	        RS_OK) {
		fprintf(stderr, "raystream-track: bench: cannot set up the pty\n");
		goto out;
	}
	struct writer w = {.pty = pty, .samples = samples, .rate_hz = rate_hz};
	pthread_t thread;
	if (pthread_create(&thread, NULL, writer_main, &w) != 0)
		goto out;
	while (n < samples) {
		struct rs_marker_sample s;
		if (rs_track_source_read(src, &s, 2000, NULL) != RS_OK)
			break;
		double now = rs_track_now_s(), written = (double)s.device_time_us * 1e-6;
		arrive[n] = s.host_time_s - written;
		parsed[n] = now - written;
		n++;
	}
	pthread_join(thread, NULL);
	if (n < samples || w.failed) {
		fprintf(stderr, "raystream-track: bench: only %d of %d paced samples arrived\n", n,
		        samples);
		goto out;
	}
	report("paced: write -> bytes read", arrive, n);
	report("paced: write -> parsed sample", parsed, n);
	code = 0;
out:
	rs_track_source_destroy(&src);
	rs_serial_pty_destroy(&pty);
	free(arrive);
	free(parsed);
	return code;
}

int track_bench(int samples, const struct rs_pose_layout *layout)
{
	printf("# raystream-track benchmark: frame %u bytes, CRC-32\n", RS_PROTO_FRAME_SIZE);
	if (parser_benchmarks() != 0)
		return 1;
	printf("# serial path through a pseudo-terminal, %d samples, one in flight at a time\n",
	       samples);
	if (latency_benchmark(samples, layout) != 0)
		return 1;
	printf("# paced at 500 Hz by a writer thread, reader blocked in poll(), %d samples\n",
	       samples);
	return paced_latency(samples, 500.0);
}
