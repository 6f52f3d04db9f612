/*
 * raystream-server: the remote render server of the paper's wireless system (DIGEST 4.3).
 * Viewers connect over TCP (docs/stream-protocol.md), send camera poses; the server renders
 * each viewer's newest pose with the library and sends it back JPEG-compressed, tagged with
 * the pose's id and time. Binds to 127.0.0.1 unless told otherwise. Bad input: one line on
 * stderr and exit 2 (usage) or 1; bad viewers: a logged disconnect, never a crash.
 */
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "app_net.h"
#include "raystream/rs_renderers.h"
#include "server.h"
#include "tool_common.h"

volatile sig_atomic_t server_signal;

static void on_signal(int sig)
{
	server_signal = sig;
}

double server_now_s(void)
{
	return (double)app_now_us() * 1e-6;
}

void server_log(const struct server *s, const char *fmt, ...)
{
	char line[512];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(line, sizeof line, fmt, ap);
	va_end(ap);
	fprintf(stderr, "raystream-server: [%.3f] %s\n", server_now_s() - s->started_s, line);
}

static void usage(FILE *to)
{
	fputs(
	    "usage: raystream-server [--scene box|cowN|FILE] [--size WxH] [--backend "
	    "cpu|egl|osmesa]\n"
	    "         [--passes N] [--lights N] [--shadows rays|map] [--threads N]\n"
	    "         [--render-threads N] [--quality 1..100] [--encoding jpeg|jpeg444|raw]\n"
	    "         [--bind ADDR] [--port N] [--port-file FILE.json] [--token TEXT]\n"
	    "         [--max-viewers N] [--link-mbps R] [--link-latency-ms L]\n"
	    "         [--read-timeout-ms T] [--stale-ms T] [--duration S] [--stats FILE.json]\n"
	    "Renders each viewer's newest pose and streams it back (docs/stream-protocol.md).\n"
	    "Defaults: scene box, 256x256, cpu, 2 passes, 1 light, quality 85 (4:2:0), bind\n"
	    "127.0.0.1, port 7878, 16 viewers, no link limit, read timeout 2000 ms, stale 200 ms.\n"
	    "--link-mbps 25 --link-latency-ms 5 emulates the paper's 802.11g link.\n",
	    to);
}

static int fail_usage(const char *fmt, const char *arg)
{
	return app_usage_error("raystream-server", fmt, arg);
}

static int parse_double(const char *v, double lo, double hi, double *out)
{
	char *end = NULL;
	double d = strtod(v, &end);
	if (!end || *end || end == v || !isfinite(d) || d < lo || d > hi)
		return 0;
	*out = d;
	return 1;
}

/* Whether `a` is one of the options that take a value (for the right usage message). */
static int known_option(const char *a)
{
	static const char *const names =
	    " --backend --bind --duration --encoding --lights --link-latency-ms --link-mbps "
	    "--max-viewers --passes --port --port-file --quality --read-timeout-ms "
	    "--render-threads --scene --shadows --size --stale-ms --stats --threads --token ";
	size_t n = strlen(a);
	for (const char *p = strstr(names, a); p; p = strstr(p + 1, a))
		if (p[-1] == ' ' && p[n] == ' ')
			return 1;
	return 0;
}

static int parse_args(int argc, char **argv, struct server_options *o)
{
	*o = (struct server_options){.scene = "box",
	                             .backend = "cpu",
	                             .bind = "127.0.0.1",
	                             .port = 7878,
	                             .width = 256,
	                             .height = 256,
	                             .passes = 2,
	                             .render_threads = 1,
	                             .max_viewers = 16,
	                             .quality = 85,
	                             .read_timeout_s = 2.0,
	                             .stale_s = 0.2};
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i];
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			exit(0);
		}
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (strncmp(a, "--", 2) != 0)
			return fail_usage("unexpected argument '%s'", a);
		if (!v)
			return fail_usage(
			    known_option(a) ? "option %s needs a value" : "unknown option '%s'", a);
		++i;
		uint32_t u = 0;
		double d = 0;
		if (!strcmp(a, "--scene"))
			o->scene = v;
		else if (!strcmp(a, "--backend"))
			o->backend = v;
		else if (!strcmp(a, "--bind"))
			o->bind = v;
		else if (!strcmp(a, "--token"))
			o->token = v;
		else if (!strcmp(a, "--port-file"))
			o->port_file = v;
		else if (!strcmp(a, "--stats"))
			o->stats = v;
		else if (!strcmp(a, "--size")) {
			if (!rs_tool_parse_size(v, &o->width, &o->height) ||
			    o->width > RS_STREAM_MAX_SIDE || o->height > RS_STREAM_MAX_SIDE)
				return fail_usage("--size wants WxH within 1..4096, not '%s'", v);
		} else if (!strcmp(a, "--port")) {
			if (!rs_tool_parse_u32(v, 0, 65535, &u))
				return fail_usage("--port wants 0..65535, not '%s'", v);
			o->port = (uint16_t)u;
		} else if (!strcmp(a, "--passes")) {
			if (!rs_tool_parse_u32(v, 1, 64, &o->passes))
				return fail_usage("--passes wants 1..64, not '%s'", v);
		} else if (!strcmp(a, "--lights")) {
			if (!rs_tool_parse_u32(v, 1, 64, &o->lights))
				return fail_usage("--lights wants 1..64, not '%s'", v);
		} else if (!strcmp(a, "--threads")) {
			if (!rs_tool_parse_u32(v, 1, 256, &o->threads))
				return fail_usage("--threads wants 1..256, not '%s'", v);
		} else if (!strcmp(a, "--render-threads")) {
			if (!rs_tool_parse_u32(v, 1, SERVER_MAX_THREADS, &o->render_threads))
				return fail_usage("--render-threads wants 1..16, not '%s'", v);
		} else if (!strcmp(a, "--max-viewers")) {
			if (!rs_tool_parse_u32(v, 1, SERVER_MAX_VIEWERS, &o->max_viewers))
				return fail_usage("--max-viewers wants 1..64, not '%s'", v);
		} else if (!strcmp(a, "--quality")) {
			if (!rs_tool_parse_u32(v, 1, 100, &u))
				return fail_usage("--quality wants 1..100, not '%s'", v);
			o->quality = (int)u;
		} else if (!strcmp(a, "--encoding")) {
			if (!strcmp(v, "jpeg"))
				o->raw = 0, o->sub = RS_JPEG_420;
			else if (!strcmp(v, "jpeg444"))
				o->raw = 0, o->sub = RS_JPEG_444;
			else if (!strcmp(v, "raw"))
				o->raw = 1;
			else
				return fail_usage("--encoding wants jpeg, jpeg444 or raw, not '%s'",
				                  v);
		} else if (!strcmp(a, "--shadows")) {
			if (!strcmp(v, "rays"))
				o->shadows = RS_SHADOW_RAYS;
			else if (!strcmp(v, "map"))
				o->shadows = RS_SHADOW_MAP;
			else
				return fail_usage("--shadows wants rays or map, not '%s'", v);
		} else if (!strcmp(a, "--link-mbps")) {
			if (!parse_double(v, 0, 1e6, &o->link_mbps))
				return fail_usage("--link-mbps wants 0..1e6, not '%s'", v);
		} else if (!strcmp(a, "--link-latency-ms")) {
			if (!parse_double(v, 0, 10000, &o->link_latency_ms))
				return fail_usage("--link-latency-ms wants 0..10000, not '%s'", v);
		} else if (!strcmp(a, "--read-timeout-ms")) {
			if (!parse_double(v, 10, 600000, &d))
				return fail_usage("--read-timeout-ms wants 10..600000, not '%s'",
				                  v);
			o->read_timeout_s = d * 1e-3;
		} else if (!strcmp(a, "--stale-ms")) {
			if (!parse_double(v, 0, 600000, &d))
				return fail_usage("--stale-ms wants 0..600000, not '%s'", v);
			o->stale_s = d * 1e-3;
		} else if (!strcmp(a, "--duration")) {
			if (!parse_double(v, 0.001, 1e7, &o->duration_s))
				return fail_usage("--duration wants seconds > 0, not '%s'", v);
		} else
			return fail_usage("unknown option '%s'", a);
	}
	if (!rs_renderer_has_backend(o->backend)) {
		fprintf(stderr, "raystream-server: unknown backend '%s' (this build has: %s)\n",
		        o->backend, rs_renderer_backends());
		return 2;
	}
	if (o->token && (strlen(o->token) > RS_STREAM_MAX_TOKEN))
		return fail_usage("--token is longer than 64 bytes: '%s'", o->token);
	if (strlen(o->scene) > RS_STREAM_MAX_SCENE)
		return fail_usage("--scene name is longer than 128 bytes: '%s'", o->scene);
	return 0;
}

static void write_stats(const struct server *s, double secs)
{
	cJSON *doc = cJSON_CreateObject();
	cJSON_AddStringToObject(doc, "scene", s->o.scene);
	cJSON_AddStringToObject(doc, "backend", s->o.backend);
	cJSON_AddNumberToObject(doc, "width", s->o.width);
	cJSON_AddNumberToObject(doc, "height", s->o.height);
	cJSON_AddNumberToObject(doc, "seconds", secs);
	cJSON_AddNumberToObject(doc, "frames_rendered", (double)s->frames_rendered);
	cJSON_AddNumberToObject(doc, "render_fps",
	                        secs > 0 ? (double)s->frames_rendered / secs : 0);
	cJSON_AddNumberToObject(doc, "render_ms_mean",
	                        s->frames_rendered ? s->render_ms_sum / (double)s->frames_rendered
	                                           : 0);
	cJSON_AddNumberToObject(doc, "disconnects", (double)s->disconnects);
	struct rs_error err = {0};
	if (rs_tool_write_json(s->o.stats, doc, &err) != RS_OK)
		fprintf(stderr, "raystream-server: %s\n", err.message);
	cJSON_Delete(doc);
}

static int run(struct server *s)
{
	struct rs_error err = {0};
	struct rs_scene *scene = NULL;
	pthread_t threads[SERVER_MAX_THREADS];
	int lfd = -1, code = 1, started = 0;
	uint16_t port = 0;
	for (const char *c = s->o.token ? s->o.token : ""; *c; ++c)
		if (*c < 0x20 || *c > 0x7e) {
			fprintf(stderr, "raystream-server: --token must be printable ASCII\n");
			return 2;
		}
	if (rs_scenegen_load(s->o.scene, &scene, &err) != RS_OK) {
		fprintf(stderr, "raystream-server: %s\n", err.message);
		return 1;
	}
	uint32_t scene_lights = (uint32_t)rs_scene_light_count(scene);
	if (s->o.lights > scene_lights) {
		fprintf(stderr, "raystream-server: --lights %u but scene '%s' has %u light(s)\n",
		        s->o.lights, s->o.scene, scene_lights);
		goto done;
	}
	if (!s->o.lights)
		s->o.lights = scene_lights ? 1u : 0u;
	s->scene = scene;
	size_t image = s->o.raw ? (size_t)s->o.width * s->o.height * 4u
	                        : rs_jpeg_bound(s->o.width, s->o.height);
	s->frame_cap = RS_STREAM_HEADER_SIZE + RS_STREAM_FRAME_FIXED + image;
	if (pipe(s->wake) != 0) {
		fprintf(stderr, "raystream-server: cannot create a pipe\n");
		goto done;
	}
	app_socket_setup(s->wake[0], 0); /* non-blocking drain */
	app_socket_setup(s->wake[1], 0); /* a full pipe never blocks a render thread */
	if (app_listen(s->o.bind, s->o.port, &lfd, &port, &err) != RS_OK) {
		fprintf(stderr, "raystream-server: %s\n", err.message);
		goto done;
	}
	s->started_s = server_now_s();
	if (server_render_start(s, threads, s->o.render_threads) != 0) {
		server_render_stop(s, threads, 0);
		goto done;
	}
	started = 1;
	if (s->o.port_file) {
		cJSON *doc = cJSON_CreateObject();
		cJSON_AddNumberToObject(doc, "port", port);
		enum rs_status st = rs_tool_write_json(s->o.port_file, doc, &err);
		cJSON_Delete(doc);
		if (st != RS_OK) {
			fprintf(stderr, "raystream-server: %s\n", err.message);
			goto done;
		}
	}
	server_log(s, "listening on %s:%u: scene %s, %ux%u, backend %s, %u pass(es), %s q%d%s",
	           s->o.bind, port, s->o.scene, s->o.width, s->o.height, s->o.backend, s->o.passes,
	           s->o.raw ? "raw" : "jpeg", s->o.quality,
	           s->o.link_mbps > 0 ? ", link emulated" : "");
	code = server_run(s, lfd);
	double secs = server_now_s() - s->started_s;
	server_log(s, "stopping: %llu frames rendered in %.2f s (%.2f fps), %llu disconnects",
	           (unsigned long long)s->frames_rendered, secs,
	           secs > 0 ? (double)s->frames_rendered / secs : 0.0,
	           (unsigned long long)s->disconnects);
	if (s->o.stats)
		write_stats(s, secs);
done:
	if (started)
		server_render_stop(s, threads, s->o.render_threads);
	if (lfd >= 0)
		close(lfd);
	for (int i = 0; i < SERVER_MAX_VIEWERS; ++i) {
		free(s->viewers[i].pending.data);
		free(s->viewers[i].inflight.data);
	}
	if (s->wake[0] > 0) {
		close(s->wake[0]);
		close(s->wake[1]);
	}
	rs_scene_destroy(&scene);
	return code;
}

int main(int argc, char **argv)
{
	static struct server s; /* large (viewer slots): not on the stack */
	int code = parse_args(argc, argv, &s.o);
	if (code)
		return code;
	pthread_mutex_init(&s.lock, NULL);
	pthread_cond_init(&s.work, NULL);
	struct sigaction sa = {.sa_handler = on_signal};
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	signal(SIGPIPE, SIG_IGN);
	code = run(&s);
	pthread_mutex_destroy(&s.lock);
	pthread_cond_destroy(&s.work);
	return code;
}
