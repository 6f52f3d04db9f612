/*
 * raystream-streambench: what the remote rendering link costs, without the tracker.
 * Renders a fixed sequence of frames once (a small orbit around the scene's camera), then
 *  1. per JPEG quality: bytes per frame, encode and decode ms, PSNR against the
 *     uncompressed frame (medians with min-max);
 *  2. the link alone: the same frames as FRAME messages (raw RGBA8 as the paper sent, and
 *     JPEG at each quality) pushed through the emulated link (token bucket + one-way
 *     latency, rs_stream.h) over a socket pair as fast as it allows, parsed and decoded by
 *     a receiver thread: delivered fps, latency from send start to decoded (median, p99).
 * The whole chain (tracker -> server -> viewer) is tools/stream-bench.sh. Not a test.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_codec.h"
#include "raystream/rs_renderers.h"
#include "raystream/rs_stream.h"
#include "tool_common.h"

#define MAX_Q 16

struct opts {
	const char *scene;
	uint32_t w, h, frames, threads, nq;
	int q[MAX_Q];
	double mbps, latency_ms;
	enum rs_jpeg_subsampling sub;
};

static int cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* median, p99, min, max of v[0..n) (sorted in place) */
static void stats(double *v, uint32_t n, double out[4])
{
	qsort(v, n, sizeof *v, cmp);
	size_t p99 = (size_t)ceil(0.99 * n) - 1u;
	out[0] = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
	out[1] = v[p99 < n ? p99 : n - 1];
	out[2] = v[0];
	out[3] = v[n - 1];
}

static double psnr(const uint8_t *a, const uint8_t *b, size_t px)
{
	double se = 0;
	for (size_t i = 0; i < px; ++i)
		for (int c = 0; c < 3; ++c) {
			double d = (double)a[4 * i + c] - b[4 * i + c];
			se += d * d;
		}
	return se == 0 ? 99.0 : 10.0 * log10(255.0 * 255.0 * (double)px * 3.0 / se);
}

/* ---- the link alone ------------------------------------------------------------------ */

struct rx {
	int fd;
	uint32_t w, h, frames;
	double *done_s; /* per frame id: decoded */
};

static void *receiver(void *arg)
{
	struct rx *r = arg;
	size_t cap = rs_stream_parser_bound((size_t)r->w * r->h * 4u);
	uint8_t *buf = malloc(cap), *in = malloc(1 << 16), *rgba = malloc((size_t)r->w * r->h * 4u);
	struct rs_jpeg *j = NULL;
	rs_jpeg_create(&j, NULL);
	struct rs_stream_parser p;
	rs_stream_parser_init(&p, buf, cap);
	uint32_t got = 0;
	while (got < r->frames) {
		ssize_t n = read(r->fd, in, 1 << 16);
		if (n <= 0)
			break;
		const uint8_t *d = in;
		size_t left = (size_t)n;
		struct rs_stream_msg m;
		while (rs_stream_parser_feed(&p, &d, &left, &m, NULL) == RS_OK) {
			if (m.type != RS_STREAM_FRAME || m.u.frame.frame_id >= r->frames)
				continue;
			if (m.u.frame.encoding == RS_STREAM_ENC_JPEG)
				rs_jpeg_decode(j, m.u.frame.data, m.u.frame.size, r->w, r->h, rgba,
				               NULL);
			else
				memcpy(rgba, m.u.frame.data, m.u.frame.size);
			r->done_s[m.u.frame.frame_id] = rs_now_ms() * 1e-3;
			++got;
		}
	}
	rs_jpeg_destroy(&j);
	free(buf);
	free(in);
	free(rgba);
	return NULL;
}

/* Push msgs[i] (len[i] bytes) through the link; fills fps and latency stats. */
static void link_run(const struct opts *o, uint8_t **msgs, const size_t *len, double *fps,
                     double lat[4])
{
	int sv[2];
	if (socketpair(AF_UNIX, SOCK_STREAM, 0, sv) != 0)
		return;
	double *start = calloc(o->frames, sizeof *start), *done = calloc(o->frames, sizeof *done);
	struct rx r = {.fd = sv[1], .w = o->w, .h = o->h, .frames = o->frames, .done_s = done};
	pthread_t t;
	pthread_create(&t, NULL, receiver, &r);
	struct rs_stream_link link;
	struct rs_stream_link_desc ld = {.rate_bits_per_s = o->mbps * 1e6,
	                                 .latency_s = o->latency_ms * 1e-3};
	rs_stream_link_init(&link, &ld, NULL);
	for (uint32_t i = 0; i < o->frames; ++i) {
		start[i] = rs_now_ms() * 1e-3;
		size_t off = 0;
		while (off < len[i]) {
			double t_now = rs_now_ms() * 1e-3;
			size_t allow = rs_stream_link_allow(&link, t_now, len[i] - off);
			if (allow == 0) {
				usleep(
				    (useconds_t)(rs_stream_link_wait_s(&link, t_now, len[i] - off) *
				                 1e6) +
				    1);
				continue;
			}
			ssize_t n = write(sv[0], msgs[i] + off, allow);
			if (n <= 0)
				break;
			rs_stream_link_spend(&link, (size_t)n);
			off += (size_t)n;
		}
	}
	pthread_join(t, NULL);
	close(sv[0]);
	close(sv[1]);
	double *l = malloc(o->frames * sizeof *l);
	for (uint32_t i = 0; i < o->frames; ++i)
		l[i] = (done[i] - start[i] + ld.latency_s) * 1e3; /* + propagation, which
		                                                     pipelines: no effect on fps */
	*fps = (double)(o->frames - 1) / (done[o->frames - 1] - done[0]);
	stats(l, o->frames, lat);
	free(l);
	free(start);
	free(done);
}

/* ---- frames, codec figures, report ---------------------------------------------------- */

static enum rs_status parse_size(void *out, const char *v, struct rs_error *err)
{
	uint32_t *wh = out;
	if (!rs_cli_parse_size(v, 4096, &wh[0], &wh[1]))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not WxH, sides 1..4096", v);
	return RS_OK;
}

static enum rs_status parse_subsampling(void *out, const char *v, struct rs_error *err)
{
	if (strcmp(v, "420") != 0 && strcmp(v, "444") != 0)
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not 420|444", v);
	*(enum rs_jpeg_subsampling *)out = !strcmp(v, "444") ? RS_JPEG_444 : RS_JPEG_420;
	return RS_OK;
}

static enum rs_status parse_qualities(void *out, const char *v, struct rs_error *err)
{
	struct opts *o = out;
	uint32_t n = 0;
	for (const char *p = v;;) {
		char *end;
		long q = strtol(p, &end, 10);
		if (end == p || q < 1 || q > 100 || n == MAX_Q || (*end && *end != ','))
			return rs_error_set(err, RS_ERR_INVALID,
			                    "'%s' is not a list of 1..%d qualities 1..100 (50,80)",
			                    v, MAX_Q);
		o->q[n++] = (int)q;
		if (!*end)
			break;
		p = end + 1;
	}
	o->nq = n;
	return RS_OK;
}

static const char about[] =
    "Renders FRAMES frames of SCENE once (a small orbit), then per JPEG quality: size,\n"
    "encode/decode time and PSNR; and all of them, raw and JPEG, pushed through an\n"
    "emulated link (by default the paper's 802.11g case: 25 Mbit/s, 5 ms one way; said on\n"
    "stderr at the start) to a receiver thread: delivered fps and latency. Progress on\n"
    "stderr. The whole chain with the apps: tools/stream-bench.sh.\n";

/* Returns 0 to run, else the exit status (0 after --help, 2 for a usage error). */
static int parse(int argc, char **argv, struct opts *o, struct rs_render_desc *render)
{
	*o = (struct opts){.scene = "box",
	                   .w = 512,
	                   .h = 512,
	                   .frames = 30,
	                   .nq = 6,
	                   .q = {50, 70, 80, 85, 90, 95},
	                   .mbps = 25,
	                   .latency_ms = 5};
	*render = (struct rs_render_desc){.passes = 2};
	uint32_t wh[2] = {o->w, o->h};
	const struct rs_cli_option opts[] = {
	    RS_CLI_STRING_OPT("--scene", &o->scene, "SCENE",
	                      "box, mirrors, animated, cowN, cowNi or a mesh file"),
	    {.name = "--size",
	     .kind = RS_CLI_CALL,
	     .out = wh,
	     .call = parse_size,
	     .arg = "WxH",
	     .help = "frame size, sides 1..4096",
	     .fallback = "512x512"},
	    RS_CLI_U32_OPT("--frames", &o->frames, 2, 1000, "frames in the sequence"),
	    {.name = "--qualities",
	     .kind = RS_CLI_CALL,
	     .out = o,
	     .call = parse_qualities,
	     .arg = "Q,Q,...",
	     .help = "JPEG qualities 1..100",
	     .fallback = "50,70,80,85,90,95"},
	    {.name = "--subsampling",
	     .kind = RS_CLI_CALL,
	     .out = &o->sub,
	     .call = parse_subsampling,
	     .arg = "420|444",
	     .help = "JPEG chroma subsampling",
	     .fallback = "420"},
	    RS_CLI_DOUBLE_OPT("--link-mbps", &o->mbps, "0.001..100000", 0.001, 1e5,
	                      "emulated link rate, Mbit/s (the paper's 802.11g)"),
	    RS_CLI_DOUBLE_OPT("--link-latency-ms", &o->latency_ms, "0..10000", 0, 1e4,
	                      "emulated one-way latency, ms"),
	};
	struct rs_cli cli = {.prog = "raystream-streambench",
	                     .usage = "[options]",
	                     .about = about,
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .render = render,
	                     .render_keys = "backend,threads,passes"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code ? code : -1;
	o->w = wh[0];
	o->h = wh[1];
	o->threads = render->threads;
	return 0;
}

/* Render the sequence: the scene camera swung +-10 degrees about the target. */
static int render_frames(const struct opts *o, const struct rs_render_desc *render,
                         uint8_t **frames, double *render_ms, char *backend, size_t cap)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	struct rs_renderer *r = NULL;
	int code = -1;
	if (rs_scenegen_load(o->scene, &scene, &err) != RS_OK)
		goto done;
	struct rs_render_desc d = *render;
	d.width = o->w;
	d.height = o->h;
	d.lights = rs_scene_light_count(scene) ? 1u : 0u;
	struct rs_error note = {0};
	if (rs_renderer_open_noted(NULL, &d, &r, &note, &err) != RS_OK ||
	    rs_renderer_set_scene(r, scene, &err) != RS_OK)
		goto done;
	if (note.message[0])
		fprintf(stderr, "raystream-streambench: %s\n", note.message);
	snprintf(backend, cap, "%s", rs_renderer_backend(r));
	fprintf(stderr, "raystream-streambench: rendering %u frames of %s on %s\n", o->frames,
	        o->scene, backend);
	struct rs_camera base = *rs_scene_camera(scene);
	for (uint32_t i = 0; i < o->frames; ++i) {
		struct rs_camera c = base;
		double a = 0.35 * sin(2.0 * RS_PI * i / o->frames);
		double dx = base.eye[0] - base.target[0], dz = base.eye[2] - base.target[2];
		c.eye[0] = base.target[0] + dx * cos(a) - dz * sin(a);
		c.eye[2] = base.target[2] + dx * sin(a) + dz * cos(a);
		struct rs_frame f = {.rgba8 = frames[i]};
		double t0 = rs_now_ms();
		if (rs_renderer_render(r, &c, &f, &err) != RS_OK)
			goto done;
		render_ms[i] = rs_now_ms() - t0;
	}
	code = 0;
done:
	if (code)
		fprintf(stderr, "raystream-streambench: %s\n", err.message);
	rs_renderer_destroy(&r);
	rs_scene_destroy(&scene);
	return code;
}

/* FRAME messages of every frame, raw (quality 0) or JPEG; encode/decode/PSNR figures. */
static void build(const struct opts *o, uint8_t **frames, int quality, uint8_t **msgs, size_t *len,
                  double fig[4][4])
{
	size_t px = (size_t)o->w * o->h, cap = rs_jpeg_bound(o->w, o->h);
	uint8_t *jpg = malloc(cap), *back = malloc(px * 4);
	double *bytes = malloc(o->frames * sizeof(double) * 4), *enc = bytes + o->frames,
	       *dec = enc + o->frames, *ps = dec + o->frames;
	struct rs_jpeg *j = NULL;
	rs_jpeg_create(&j, NULL);
	for (uint32_t i = 0; i < o->frames; ++i) {
		struct rs_stream_msg m = {.type = RS_STREAM_FRAME};
		m.u.frame = (struct rs_stream_frame){
		    .frame_id = i, .width = (uint16_t)o->w, .height = (uint16_t)o->h};
		size_t n = px * 4;
		enc[i] = dec[i] = 0;
		ps[i] = 99;
		if (quality == 0) {
			m.u.frame.encoding = RS_STREAM_ENC_RGBA8;
			m.u.frame.data = frames[i];
		} else {
			double t0 = rs_now_ms();
			rs_jpeg_encode(j, frames[i], o->w, o->h, quality, o->sub, jpg, cap, &n,
			               NULL);
			double t1 = rs_now_ms();
			rs_jpeg_decode(j, jpg, n, o->w, o->h, back, NULL);
			dec[i] = rs_now_ms() - t1;
			enc[i] = t1 - t0;
			ps[i] = psnr(frames[i], back, px);
			m.u.frame.encoding = RS_STREAM_ENC_JPEG;
			m.u.frame.data = jpg;
		}
		m.u.frame.size = (uint32_t)n;
		bytes[i] = (double)n;
		msgs[i] = malloc(n + 64);
		rs_stream_encode(&m, msgs[i], n + 64, &len[i], NULL);
	}
	stats(bytes, o->frames, fig[0]);
	stats(enc, o->frames, fig[1]);
	stats(dec, o->frames, fig[2]);
	stats(ps, o->frames, fig[3]);
	rs_jpeg_destroy(&j);
	free(jpg);
	free(back);
	free(bytes);
}

int main(int argc, char **argv)
{
	struct opts o;
	struct rs_render_desc render;
	int code = parse(argc, argv, &o, &render);
	if (code)
		return code < 0 ? 0 : code;
	fprintf(stderr,
	        "raystream-streambench: emulating a %g Mbit/s link with %g ms latency "
	        "(--link-mbps, --link-latency-ms)\n",
	        o.mbps, o.latency_ms);
	size_t px = (size_t)o.w * o.h;
	uint8_t **frames = calloc(o.frames, sizeof *frames),
	        **msgs = calloc(o.frames, sizeof *msgs);
	size_t *len = calloc(o.frames, sizeof *len);
	double *render_ms = calloc(o.frames, sizeof *render_ms), rs[4];
	for (uint32_t i = 0; i < o.frames; ++i)
		frames[i] = malloc(px * 4);
	char backend[16] = "";
	if (render_frames(&o, &render, frames, render_ms, backend, sizeof backend) != 0)
		return 1;
	stats(render_ms, o.frames, rs);
	printf("scene %s %ux%u, %u frames, %s render %.1f ms median (%.1f-%.1f) = %.2f fps; "
	       "link %.1f Mbit/s + %.1f ms\n",
	       o.scene, o.w, o.h, o.frames, backend, rs[0], rs[2], rs[3], 1e3 / rs[0], o.mbps,
	       o.latency_ms);
	printf("%-8s %10s %18s %18s %18s %9s %12s %12s\n", "encoding", "KB/frame", "encode ms",
	       "decode ms", "PSNR dB (min)", "link fps", "lat med ms", "lat p99 ms");
	for (uint32_t k = 0; k <= o.nq; ++k) {
		int q = k == 0 ? 0 : o.q[k - 1];
		double fig[4][4], fps = 0, lat[4] = {0};
		char name[16];
		snprintf(name, sizeof name, q ? "%s q%d" : "raw",
		         o.sub == RS_JPEG_444 ? "444" : "420", q);
		fprintf(stderr, "raystream-streambench: [%u/%u] %s: encode, link\n", k + 1,
		        o.nq + 1, name);
		build(&o, frames, q, msgs, len, fig);
		link_run(&o, msgs, len, &fps, lat);
		printf("%-8s %10.1f %6.2f (%4.2f-%5.2f) %6.2f (%4.2f-%5.2f) %8.2f (%6.2f) %9.2f "
		       "%12.1f "
		       "%12.1f\n",
		       name, fig[0][0] / 1024.0, fig[1][0], fig[1][2], fig[1][3], fig[2][0],
		       fig[2][2], fig[2][3], fig[3][0], fig[3][2], fps, lat[0], lat[1]);
		for (uint32_t i = 0; i < o.frames; ++i)
			free(msgs[i]);
	}
	for (uint32_t i = 0; i < o.frames; ++i)
		free(frames[i]);
	free(frames);
	free(msgs);
	free(len);
	free(render_ms);
	return 0;
}
