/*
 * raystream-viewer: the tracked handheld viewer (DIGEST 4.3). Its pose comes from any
 * tracker URI (rs_tracker.h), the display calibration turns it into a camera (rs_view.h),
 * and it shows frames rendered locally or received from raystream-server. A status line
 * (stdout and window title) gives fps, motion-to-photon latency and link rate.
 * --headless writes frames to files instead of a window. Keys: q/Esc quit, space or m
 * switch local/remote, r recentre. Bad input: one line on stderr, exit 2 (usage) or 1.
 */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "raystream/rs_cli.h"

#include "app_net.h"
#include "viewer.h"

static void usage(FILE *to)
{
	fputs(
	    "usage: raystream-viewer [--tracker URI] [--server HOST:PORT] [--scene box|cowN|FILE]\n"
	    "         [--size WxH] [--view camera|window] [--eye X,Y,Z] [--eye-frame "
	    "screen|tracker]\n"
	    "         [--screen WxH_METRES] [--fov DEG] [--scale UNITS_PER_M] [--layout "
	    "FILE.json]\n"
	    "         [--local] [--backend auto|cpu|egl|osmesa] [--present direct|readback]\n"
	    "         [--passes N] [--threads N] [--quality N] [--token TEXT] [--headless]\n"
	    "         [--out DIR] [--every N] [--frames N] [--duration S] [--stats FILE.json]\n"
	    "         [--verify-local] [--pose-id-base N] [--last FILE.png] [--linger S]\n"
	    "         [--target-fps N] [--render-scale 1|0.71|0.5|0.35|0.25] [--predict on|off]\n"
	    "Defaults: tracker sim:realtime=1, scene box, 256x256, camera view (the scene's own\n"
	    "camera at the first pose, then moving with the handheld; --view window: "
	    "head-coupled,\n"
	    "the eye 0.35 m in front of a 58 mm square screen); backend auto (the GPU: in a "
	    "window\n"
	    "frames are drawn straight into it; cpu with one line when no GL context opens);\n"
	    "remote when --server is given. Key r recentres onto the scene's camera.\n"
	    "--target-fps 30 (0: off): local frames in the window render at a smaller scale,\n"
	    "upscaled, while they miss the budget (files and --headless stay full size).\n"
	    "--predict on: each pose is moved ahead by the measured latency (at most 30 ms).\n",
	    to);
}

static int fail_usage(const char *fmt, const char *arg)
{
	return app_usage_error("raystream-viewer", fmt, arg);
}

/* "a,b,c" (n numbers) or "AxB" (n = 2, sep 'x'). */
static int parse_numbers(const char *v, char sep, int n, double *out)
{
	const char *p = v;
	for (int i = 0; i < n; ++i) {
		char *end = NULL;
		out[i] = strtod(p, &end);
		if (end == p || !isfinite(out[i]))
			return 0;
		if (i + 1 < n && *end != sep)
			return 0;
		p = end + (i + 1 < n);
		if (i + 1 == n && *end)
			return 0;
	}
	return 1;
}

/* Whether `a` is one of the options that take a value (for the right usage message). */
static int known_option(const char *a)
{
	static const char *const names =
	    " --backend --duration --every --eye --eye-frame --fov --frames --last --layout "
	    "--linger --out "
	    "--passes --pose-id-base --predict --present --quality --render-scale --target-fps "
	    "--scale "
	    "--scene --screen --server --size "
	    "--stats "
	    "--threads --token --tracker --view ";
	size_t n = strlen(a);
	for (const char *p = strstr(names, a); p; p = strstr(p + 1, a))
		if (p[-1] == ' ' && p[n] == ' ')
			return 1;
	return 0;
}

static int parse_args(int argc, char **argv, struct viewer_options *o)
{
	*o = (struct viewer_options){.tracker = "sim:realtime=1",
	                             .scene = "box",
	                             .backend = "auto",
	                             .width = 256,
	                             .height = 256,
	                             .passes = 2,
	                             .every = 1,
	                             .target_fps = 30.0,
	                             .fixed_level = -1,
	                             /* the paper's mode: the start frame is the scene's own
	                              * camera (a head-coupled window's frustum is narrower) */
	                             .cal = {.mode = RS_VIEW_CAMERA}};
	int local = 0;
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i];
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			exit(0);
		}
		if (!strcmp(a, "--headless")) {
			o->headless = 1;
			continue;
		}
		if (!strcmp(a, "--local")) {
			local = 1;
			continue;
		}
		if (!strcmp(a, "--verify-local")) {
			o->verify_local = 1;
			continue;
		}
		if (strncmp(a, "--", 2) != 0)
			return fail_usage("unexpected argument '%s'", a);
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!v)
			return fail_usage(
			    known_option(a) ? "option %s needs a value" : "unknown option '%s'", a);
		++i;
		uint32_t u = 0;
		double d[3];
		if (!strcmp(a, "--tracker"))
			o->tracker = v;
		else if (!strcmp(a, "--server"))
			o->server = v;
		else if (!strcmp(a, "--scene"))
			o->scene = v;
		else if (!strcmp(a, "--backend"))
			o->backend = v;
		else if (!strcmp(a, "--token"))
			o->token = v;
		else if (!strcmp(a, "--out"))
			o->out_dir = v;
		else if (!strcmp(a, "--stats"))
			o->stats = v;
		else if (!strcmp(a, "--layout"))
			o->layout = v;
		else if (!strcmp(a, "--last"))
			o->last = v;
		else if (!strcmp(a, "--size")) {
			if (!rs_cli_parse_size(v, RS_STREAM_MAX_SIDE, &o->width, &o->height) ||
			    o->width > RS_STREAM_MAX_SIDE || o->height > RS_STREAM_MAX_SIDE)
				return fail_usage("--size wants WxH within 1..4096, not '%s'", v);
		} else if (!strcmp(a, "--target-fps")) {
			if (!parse_numbers(v, ',', 1, d) || !(d[0] >= 0 && d[0] <= 1000))
				return fail_usage("--target-fps wants 0..1000 (0: off), not '%s'",
				                  v);
			o->target_fps = d[0];
		} else if (!strcmp(a, "--render-scale")) {
			o->fixed_level = -1;
			for (int k = 0; k < APP_PACE_LEVELS && parse_numbers(v, ',', 1, d); ++k)
				if (d[0] == app_pace_scales[k])
					o->fixed_level = k;
			if (o->fixed_level < 0)
				return fail_usage(
				    "--render-scale wants 1, 0.71, 0.5, 0.35 or 0.25, "
				    "not '%s'",
				    v);
		} else if (!strcmp(a, "--predict")) {
			if (strcmp(v, "on") != 0 && strcmp(v, "off") != 0)
				return fail_usage("--predict wants on or off, not '%s'", v);
			o->no_predict = !strcmp(v, "off");
		} else if (!strcmp(a, "--present")) {
			if (!strcmp(v, "direct") || !strcmp(v, "readback"))
				o->readback = !strcmp(v, "readback");
			else
				return fail_usage("--present wants direct or readback, not '%s'",
				                  v);
		} else if (!strcmp(a, "--view")) {
			if (!strcmp(v, "window"))
				o->cal.mode = RS_VIEW_HEAD_COUPLED;
			else if (!strcmp(v, "camera"))
				o->cal.mode = RS_VIEW_CAMERA;
			else
				return fail_usage("--view wants window or camera, not '%s'", v);
		} else if (!strcmp(a, "--eye")) {
			if (!parse_numbers(v, ',', 3, d))
				return fail_usage("--eye wants X,Y,Z in metres, not '%s'", v);
			memcpy(o->cal.eye, d, sizeof d);
		} else if (!strcmp(a, "--eye-frame")) {
			if (!strcmp(v, "screen"))
				o->cal.eye_frame = RS_VIEW_EYE_IN_SCREEN;
			else if (!strcmp(v, "tracker"))
				o->cal.eye_frame = RS_VIEW_EYE_IN_TRACKER;
			else
				return fail_usage("--eye-frame wants screen or tracker, not '%s'",
				                  v);
		} else if (!strcmp(a, "--screen")) {
			if (!parse_numbers(v, 'x', 2, d) || !(d[0] > 0) || !(d[1] > 0))
				return fail_usage("--screen wants WxH in metres, not '%s'", v);
			o->cal.screen_width_m = d[0];
			o->cal.screen_height_m = d[1];
		} else if (!strcmp(a, "--fov")) {
			if (!parse_numbers(v, ',', 1, d) || !(d[0] > 0 && d[0] < 180))
				return fail_usage("--fov wants degrees in (0, 180), not '%s'", v);
			o->cal.fov_y_deg = d[0];
		} else if (!strcmp(a, "--scale")) {
			if (!parse_numbers(v, ',', 1, d) || !(d[0] > 0))
				return fail_usage(
				    "--scale wants scene units per metre > 0, not '%s'", v);
			o->cal.scene_units_per_m = d[0];
		} else if (!strcmp(a, "--duration")) {
			if (!parse_numbers(v, ',', 1, d) || !(d[0] > 0))
				return fail_usage("--duration wants seconds > 0, not '%s'", v);
			o->duration_s = d[0];
		} else if (!strcmp(a, "--linger")) {
			if (!parse_numbers(v, ',', 1, d) || !(d[0] >= 0 && d[0] <= 3600))
				return fail_usage("--linger wants seconds 0..3600, not '%s'", v);
			o->linger_s = d[0];
		} else if (!strcmp(a, "--passes")) {
			if (!rs_cli_parse_u32(v, 1, 64, &o->passes))
				return fail_usage("--passes wants 1..64, not '%s'", v);
		} else if (!strcmp(a, "--threads")) {
			if (!rs_cli_parse_u32(v, 1, 256, &o->threads))
				return fail_usage("--threads wants 1..256, not '%s'", v);
		} else if (!strcmp(a, "--every")) {
			if (!rs_cli_parse_u32(v, 1, 1000000, &o->every))
				return fail_usage("--every wants 1..1000000, not '%s'", v);
		} else if (!strcmp(a, "--frames")) {
			if (!rs_cli_parse_u32(v, 1, 100000000, &o->frames))
				return fail_usage("--frames wants 1..1e8, not '%s'", v);
		} else if (!strcmp(a, "--pose-id-base")) {
			if (!rs_cli_parse_u32(v, 0, 4000000000u, &o->pose_id_base))
				return fail_usage("--pose-id-base wants 0..4e9, not '%s'", v);
		} else if (!strcmp(a, "--quality")) {
			if (!rs_cli_parse_u32(v, 1, 100, &u))
				return fail_usage("--quality wants 1..100, not '%s'", v);
			o->quality = (int)u;
		} else
			return fail_usage("unknown option '%s'", a);
	}
	o->start_remote = o->server && !local;
	if (o->verify_local && !o->server)
		return fail_usage("%s", "--verify-local needs --server");
	if (o->headless && !o->out_dir && !o->stats && !o->frames && !o->duration_s)
		return fail_usage("%s", "--headless needs --out, --stats, --frames or --duration");
	if (o->out_dir) {
		struct stat st;
		if (stat(o->out_dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
			fprintf(stderr, "raystream-viewer: --out '%s' is not a directory\n",
			        o->out_dir);
			return 2;
		}
	}
	return 0;
}

int viewer_main(struct viewer_options *o);

int main(int argc, char **argv)
{
	struct viewer_options o;
	int code = parse_args(argc, argv, &o);
	return code ? code : viewer_main(&o);
}
