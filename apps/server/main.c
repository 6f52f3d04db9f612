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

#include "raystream/rs_cli.h"
#include "raystream/rs_scenegen.h"

#include "app_net.h"
#include "raystream/rs_renderers.h"
#include "server.h"

volatile sig_atomic_t server_signal;

static void on_signal(int sig)
{
	server_signal = sig;
}

double server_now_s(void)
{
	return rs_now_ms() * 1e-3;
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

static const struct rs_cli prog = {.prog = "raystream-server"}; /* messages after parsing */

/* A macro's value as text, for the ranges --help shows. */
#define STR_(x) #x
#define STR(x) STR_(x)

static const char about[] =
    "Renders each viewer's newest pose and streams it back (docs/stream-protocol.md).\n"
    "Backend auto renders on the GPU where a GL context opens, else on cpu with a note.\n"
    "--link-mbps 25 --link-latency-ms 5 emulates the paper's 802.11g link.\n";

static enum rs_status parse_encoding(void *out, const char *v, struct rs_error *err)
{
	struct server_options *o = out;
	if (!strcmp(v, "jpeg"))
		o->raw = 0, o->sub = RS_JPEG_420;
	else if (!strcmp(v, "jpeg444"))
		o->raw = 0, o->sub = RS_JPEG_444;
	else if (!strcmp(v, "raw"))
		o->raw = 1;
	else
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not jpeg, jpeg444 or raw", v);
	return RS_OK;
}

/* Returns 0 to run, else the exit status (0 after --help, 2 for a usage error). */
static int parse_args(int argc, char **argv, struct server_options *o)
{
	*o = (struct server_options){.scene = "box",
	                             .bind = "127.0.0.1",
	                             .width = 256,
	                             .height = 256,
	                             .render_threads = 1,
	                             .max_viewers = 16};
	struct rs_render_desc desc = {.backend = "auto", .passes = 2};
	uint32_t port = 7878, quality = 85;
	double read_timeout_ms = 2000, stale_ms = 200;
	struct app_size size = {&o->width, &o->height};
	const struct rs_cli_option opts[] = {
	    {.name = "--scene",
	     .kind = RS_CLI_STRING,
	     .out = &o->scene,
	     .arg = "box|cowN|FILE",
	     .help = "what to render (at most 128 bytes)"},
	    {.name = "--size",
	     .kind = RS_CLI_CALL,
	     .out = &size,
	     .call = app_parse_size,
	     .arg = "WxH",
	     .help = "image size, sides 1..4096",
	     .fallback = "256x256"},
	    {.name = "--lights",
	     .kind = RS_CLI_U32,
	     .out = &o->lights,
	     .arg = "1..64",
	     .help = "use the scene's first N lights",
	     .min = 1,
	     .max = 64,
	     .fallback = "all (the library's default)"},
	    {.name = "--render-threads",
	     .kind = RS_CLI_U32,
	     .out = &o->render_threads,
	     .arg = "1.." STR(SERVER_MAX_THREADS),
	     .help = "render threads, each its own renderer",
	     .min = 1,
	     .max = SERVER_MAX_THREADS},
	    RS_CLI_U32_OPT("--quality", &quality, 1, 100, "JPEG quality unless a viewer asks"),
	    {.name = "--encoding",
	     .kind = RS_CLI_CALL,
	     .out = o,
	     .call = parse_encoding,
	     .arg = "jpeg|jpeg444|raw",
	     .help = "frames as JPEG 4:2:0, JPEG 4:4:4 or raw RGBA8",
	     .fallback = "jpeg"},
	    RS_CLI_STRING_OPT("--bind", &o->bind, "ADDR", "the address to listen on"),
	    RS_CLI_U32_OPT("--port", &port, 0, 65535, "TCP port; 0: any free one"),
	    RS_CLI_STRING_OPT("--port-file", &o->port_file, "FILE.json",
	                      "write {\"port\": N} once listening"),
	    RS_CLI_STRING_OPT("--token", &o->token, "TEXT",
	                      "viewers must present it (printable, at most 64 bytes)"),
	    {.name = "--max-viewers",
	     .kind = RS_CLI_U32,
	     .out = &o->max_viewers,
	     .arg = "1.." STR(SERVER_MAX_VIEWERS),
	     .help = "viewers served at once",
	     .min = 1,
	     .max = SERVER_MAX_VIEWERS},
	    {.name = "--link-mbps",
	     .kind = RS_CLI_DOUBLE,
	     .out = &o->link_mbps,
	     .arg = "0..1e6",
	     .help = "emulated link rate in Mbit/s; 0: no limit",
	     .max = 1e6},
	    RS_CLI_DOUBLE_OPT("--link-latency-ms", &o->link_latency_ms, "0..10000", 0, 10000,
	                      "emulated one-way link latency"),
	    RS_CLI_DOUBLE_OPT("--read-timeout-ms", &read_timeout_ms, "10..600000", 10, 600000,
	                      "a viewer silent mid-message or without hello is dropped"),
	    RS_CLI_DOUBLE_OPT("--stale-ms", &stale_ms, "0..600000", 0, 600000,
	                      "a pending frame older than this yields to a newer pose"),
	    RS_CLI_DOUBLE_OPT("--target-fps", &o->target_fps, "0..1000", 0, 1000,
	                      "per viewer dynamic resolution budget (frames sent smaller, the "
	                      "viewer scales up); 0: off"),
	    {.name = "--duration",
	     .kind = RS_CLI_DOUBLE,
	     .out = &o->duration_s,
	     .arg = "S",
	     .help = "stop after S seconds (0.001..1e7)",
	     .min = 0.001,
	     .max = 1e7,
	     .fallback = "until SIGINT/SIGTERM"},
	    RS_CLI_STRING_OPT("--stats", &o->stats, "FILE.json", "what the run rendered, at exit"),
	    RS_CLI_U32_OPT("--frame", &o->frame, 0, 10000000,
	                   "the frame of a scene that moves (animated, cowN, cowNi)"),
	    RS_CLI_U32_OPT("--animate", &o->animate, 0, 1000,
	                   "play a scene that moves at FPS frames a second from --frame; 0: still"),
	};
	struct rs_cli cli = {.prog = prog.prog,
	                     .usage = "[options]",
	                     .about = about,
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .render = &desc,
	                     .render_keys = "backend,passes,shadows,threads,kernels"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code ? code : -1;
	o->backend = desc.backend;
	o->passes = desc.passes;
	o->shadows = desc.shadows;
	o->shadow_map_size = desc.shadow_map_size;
	o->shadow_filter = desc.shadow_filter;
	o->kernels = desc.kernels;
	o->threads = desc.threads;
	o->port = (uint16_t)port;
	o->quality = (int)quality;
	o->read_timeout_s = read_timeout_ms * 1e-3;
	o->stale_s = stale_ms * 1e-3;
	if (!rs_renderer_has_backend(o->backend))
		return rs_cli_usage_error(&cli,
		                          "--backend: '%s' is not part of this build (have: %s)",
		                          o->backend, rs_renderer_backends());
	if (o->token && (strlen(o->token) > RS_STREAM_MAX_TOKEN))
		return rs_cli_usage_error(&cli, "--token: longer than 64 bytes");
	if (strlen(o->scene) > RS_STREAM_MAX_SCENE)
		return rs_cli_usage_error(&cli, "--scene: name longer than 128 bytes");
	if ((o->frame || o->animate) && !rs_scenegen_moves(o->scene))
		return rs_cli_usage_error(
		    &cli, "--frame/--animate: scene '%s' does not move (animated, cowN, cowNi)",
		    o->scene);
	if (o->animate && o->shadows == RS_SHADOW_MAP)
		return rs_cli_usage_error(&cli, "--animate: shadow maps are made once per scene; "
		                                "use --shadows rays");
	/* Output targets checked now, so a bad path fails before the run and not after it. */
	const char *outputs[] = {o->stats, o->port_file};
	for (size_t i = 0; i < 2; ++i) {
		struct rs_error err = {0};
		if (outputs[i] && rs_cli_check_output(outputs[i], &err) != RS_OK)
			return rs_cli_fail(&cli, &err);
	}
	return 0;
}

/* The server renders on a GL backend, where --kernels means something (auto may have fallen
 * back to cpu, which has no kernels: then neither the log nor the stats name any). */
static bool server_gl_kernels(const struct server *s)
{
	return s->backend && strcmp(s->backend, "cpu") != 0;
}

/* 0, or 1 after reporting that the file could not be written. */
static int write_stats(const struct server *s, double secs)
{
	cJSON *doc = cJSON_CreateObject();
	cJSON_AddStringToObject(doc, "scene", s->o.scene);
	cJSON_AddStringToObject(doc, "backend", s->backend);
	if (server_gl_kernels(s)) { /* the CPU backend has none (auto may have fallen back) */
		char kernels[16];
		rs_render_desc_get(&(struct rs_render_desc){.kernels = s->o.kernels}, "kernels",
		                   kernels, sizeof kernels, NULL);
		cJSON_AddStringToObject(doc, "kernels", kernels);
	}
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
	if (s->o.animate)
		cJSON_AddNumberToObject(doc, "scene_frame", s->scene_frame);
	struct rs_error err = {0};
	int code = app_write_json(s->o.stats, doc, &err) != RS_OK ? rs_cli_fail(&prog, &err) : 0;
	cJSON_Delete(doc);
	return code;
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
	if (rs_scenegen_load_frame(s->o.scene, s->o.frame, s->o.animate, &scene, &err) != RS_OK) {
		fprintf(stderr, "raystream-server: %s\n", err.message);
		return 1;
	}
	uint32_t scene_lights = (uint32_t)rs_scene_light_count(scene);
	if (s->o.lights > scene_lights) {
		fprintf(stderr, "raystream-server: --lights %u but scene '%s' has %u light(s)\n",
		        s->o.lights, s->o.scene, scene_lights);
		goto done;
	}
	/* 0 stays 0: all of the scene's lights, as raystream-render and the library draw it */
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
		enum rs_status st = app_write_json(s->o.port_file, doc, &err);
		cJSON_Delete(doc);
		if (st != RS_OK) {
			fprintf(stderr, "raystream-server: %s\n", err.message);
			goto done;
		}
	}
	server_log(s, "listening on %s:%u: scene %s, %ux%u, backend %s%s, %u pass(es), %s q%d%s",
	           s->o.bind, port, s->o.scene, s->o.width, s->o.height, s->backend,
	           server_gl_kernels(s) && s->o.kernels == RS_KERNELS_COMPUTE ? " (compute kernels)"
	                                                                      : "",
	           s->o.passes, s->o.raw ? "raw" : "jpeg", s->o.quality,
	           s->o.link_mbps > 0 ? ", link emulated" : "");
	code = server_run(s, lfd);
	double secs = server_now_s() - s->started_s;
	server_log(s, "stopping: %llu frames rendered in %.2f s (%.2f fps), %llu disconnects",
	           (unsigned long long)s->frames_rendered, secs,
	           secs > 0 ? (double)s->frames_rendered / secs : 0.0,
	           (unsigned long long)s->disconnects);
	if (s->o.stats && write_stats(s, secs) != 0 && code == 0)
		code = 1;
done:
	if (started)
		server_render_stop(s, threads, s->o.render_threads);
	if (lfd >= 0)
		close(lfd);
	for (int i = 0; i < SERVER_SLOTS; ++i) {
		free(s->viewers[i].pending.data);
		free(s->viewers[i].refine_acc);
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
		return code < 0 ? 0 : code;
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
