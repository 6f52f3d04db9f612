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

#include "raystream/rs_cli.h"
#include "raystream/rs_scenegen.h"

#include "app_net.h"
#include "viewer.h"

static const char about[] =
    "Shows the scene from a tracked handheld: frames rendered here, or by raystream-server\n"
    "(remote when --server is given, unless --local). --view camera starts at the scene's\n"
    "own camera and moves with the handheld; --view window is head-coupled, the eye in\n"
    "front of the screen. Backend auto: the GPU (in a window frames are drawn straight\n"
    "into it), cpu with one line when no GL context opens. --target-fps: local frames in\n"
    "the window render at a smaller scale, upscaled, while they miss the budget (files and\n"
    "--headless stay full size). --predict on moves each pose ahead by the measured\n"
    "latency (at most 30 ms). --refine on averages sub-pixel samples while the pose is\n"
    "still (0.5 mm, 0.05 degrees): antialiasing; any motion restarts it; off with\n"
    "--animate, where the scene moves.\n"
    "Keys: q/Esc quit, space or m local/remote, r recentre.\n";

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

/* `value` as the index of one of names[0..n), or RS_ERR_INVALID naming them. */
static enum rs_status pick(const char *value, const char *const *names, int n, int *out,
                           struct rs_error *err)
{
	for (int i = 0; i < n; ++i)
		if (!strcmp(value, names[i])) {
			*out = i;
			return RS_OK;
		}
	return rs_error_set(err, RS_ERR_INVALID, "'%s' is not %s or %s", value, names[0],
	                    names[n - 1]);
}

static enum rs_status parse_view(void *out, const char *v, struct rs_error *err)
{
	static const char *const names[] = {"camera", "window"};
	int i = 0;
	enum rs_status st = pick(v, names, 2, &i, err);
	*(enum rs_view_mode *)out = i ? RS_VIEW_HEAD_COUPLED : RS_VIEW_CAMERA;
	return st;
}

static enum rs_status parse_eye_frame(void *out, const char *v, struct rs_error *err)
{
	static const char *const names[] = {"screen", "tracker"};
	int i = 0;
	enum rs_status st = pick(v, names, 2, &i, err);
	*(enum rs_view_eye_frame *)out = i ? RS_VIEW_EYE_IN_TRACKER : RS_VIEW_EYE_IN_SCREEN;
	return st;
}

static enum rs_status parse_present(void *out, const char *v, struct rs_error *err)
{
	static const char *const names[] = {"direct", "readback"};
	return pick(v, names, 2, out, err);
}

static enum rs_status parse_predict(void *out, const char *v, struct rs_error *err)
{
	static const char *const names[] = {"on", "off"};
	return pick(v, names, 2, out, err);
}

static enum rs_status parse_render_scale(void *out, const char *v, struct rs_error *err)
{
	double d;
	for (int k = 0; k < APP_PACE_LEVELS && parse_numbers(v, ',', 1, &d); ++k)
		if (d == app_pace_scales[k]) {
			*(int *)out = k;
			return RS_OK;
		}
	return rs_error_set(err, RS_ERR_INVALID, "'%s' is not 1, 0.71, 0.5, 0.35 or 0.25", v);
}

static enum rs_status parse_eye(void *out, const char *v, struct rs_error *err)
{
	if (!parse_numbers(v, ',', 3, out))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not X,Y,Z in metres", v);
	return RS_OK;
}

static enum rs_status parse_screen(void *out, const char *v, struct rs_error *err)
{
	double d[2];
	struct rs_view_calibration *cal = out;
	if (!parse_numbers(v, 'x', 2, d) || !(d[0] > 0) || !(d[1] > 0))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not WxH in metres > 0", v);
	cal->screen_width_m = d[0];
	cal->screen_height_m = d[1];
	return RS_OK;
}

/* A number > 0 (and below 180 for --fov): open ranges RS_CLI_DOUBLE cannot state. */
static enum rs_status parse_positive(void *out, const char *v, struct rs_error *err)
{
	if (!parse_numbers(v, ',', 1, out) || !(*(double *)out > 0))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not a number > 0", v);
	return RS_OK;
}

static enum rs_status parse_fov(void *out, const char *v, struct rs_error *err)
{
	if (!parse_numbers(v, ',', 1, out) || !(*(double *)out > 0 && *(double *)out < 180))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not degrees in (0, 180)", v);
	return RS_OK;
}

#define CALL(NAME, OUT, FN, ARG, HELP, DEF)                                                        \
	{                                                                                          \
		.name = (NAME), .kind = RS_CLI_CALL, .out = (OUT), .call = (FN), .arg = (ARG),     \
		.help = (HELP), .fallback = (DEF)                                                  \
	}

/* Returns 0 to run, else the exit status (0 after --help, 2 for a usage error). */
static int parse_args(int argc, char **argv, struct viewer_options *o)
{
	*o = (struct viewer_options){.tracker = "sim:realtime=1",
	                             .scene = "box",
	                             .width = 256,
	                             .height = 256,
	                             .every = 1,
	                             .target_fps = 30.0,
	                             .fixed_level = -1,
	                             /* the paper's mode: the start frame is the scene's own
	                              * camera (a head-coupled window's frustum is narrower) */
	                             .cal = {.mode = RS_VIEW_CAMERA}};
	struct rs_render_desc desc = {.backend = "auto", .passes = 2};
	struct app_size size = {&o->width, &o->height};
	bool local = false, headless = false, verify = false;
	uint32_t quality = 0;
	const struct rs_cli_option opts[] = {
	    RS_CLI_STRING_OPT("--tracker", &o->tracker, "URI", "pose source (rs_tracker.h)"),
	    RS_CLI_STRING_OPT("--server", &o->server, "HOST:PORT", "raystream-server to use"),
	    RS_CLI_STRING_OPT("--scene", &o->scene, "box|cowN|FILE", "what to show"),
	    CALL("--size", &size, app_parse_size, "WxH", "image size, sides 1..4096", "256x256"),
	    CALL("--view", &o->cal.mode, parse_view, "camera|window",
	         "scene camera moved by the handheld, or head-coupled", "camera"),
	    CALL("--eye", o->cal.eye, parse_eye, "X,Y,Z", "eye position in metres",
	         "0.35 m in front"),
	    CALL("--eye-frame", &o->cal.eye_frame, parse_eye_frame, "screen|tracker",
	         "the frame --eye is given in", "screen"),
	    CALL("--screen", &o->cal, parse_screen, "WxH_METRES", "the display's size",
	         "58 mm square"),
	    CALL("--fov", &o->cal.fov_y_deg, parse_fov, "DEG", "vertical field of view (0, 180)",
	         "the scene's"),
	    CALL("--scale", &o->cal.scene_units_per_m, parse_positive, "UNITS_PER_M",
	         "scene units per metre > 0", "the scene's"),
	    RS_CLI_STRING_OPT("--layout", &o->layout, "FILE.json", "marker layout for the tracker"),
	    RS_CLI_FLAG_OPT("--local", &local, "render here even with --server"),
	    CALL("--present", &o->readback, parse_present, "direct|readback",
	         "GPU frames drawn straight, or read back and uploaded", "direct"),
	    {.name = "--quality",
	     .kind = RS_CLI_U32,
	     .out = &quality,
	     .arg = "1..100",
	     .help = "JPEG quality asked of the server",
	     .min = 1,
	     .max = 100,
	     .fallback = "the server's"},
	    RS_CLI_STRING_OPT("--token", &o->token, "TEXT", "the server's token"),
	    RS_CLI_FLAG_OPT("--headless", &headless, "no window: frames to files"),
	    RS_CLI_STRING_OPT("--out", &o->out_dir, "DIR", "frames as PNG (created)"),
	    RS_CLI_U32_OPT("--every", &o->every, 1, 1000000, "write every Nth frame to --out"),
	    {.name = "--frames",
	     .kind = RS_CLI_U32,
	     .out = &o->frames,
	     .arg = "1..1e8",
	     .help = "stop after N frames",
	     .min = 1,
	     .max = 100000000,
	     .fallback = "no limit"},
	    CALL("--duration", &o->duration_s, parse_positive, "S", "stop after S seconds > 0",
	         "no limit"),
	    RS_CLI_STRING_OPT("--stats", &o->stats, "FILE.json", "what the run measured, at exit"),
	    RS_CLI_FLAG_OPT("--verify-local", &verify,
	                    "compare remote frames with local ones (remote refinement off)"),
	    {.name = "--pose-id-base",
	     .kind = RS_CLI_U32,
	     .out = &o->pose_id_base,
	     .arg = "0..4000000000",
	     .help = "the first pose id",
	     .max = 4000000000u},
	    RS_CLI_STRING_OPT("--last", &o->last, "FILE.png", "the last frame, at exit"),
	    RS_CLI_DOUBLE_OPT("--linger", &o->linger_s, "0..3600", 0, 3600,
	                      "seconds the window stays after the run"),
	    RS_CLI_DOUBLE_OPT("--target-fps", &o->target_fps, "0..1000", 0, 1000,
	                      "dynamic resolution budget; 0: off"),
	    CALL("--render-scale", &o->fixed_level, parse_render_scale, "1|0.71|0.5|0.35|0.25",
	         "a fixed scale instead", "dynamic"),
	    CALL("--predict", &o->no_predict, parse_predict, "on|off",
	         "poses moved ahead by the latency", "on"),
	    RS_CLI_U32_OPT("--frame", &o->frame, 0, 10000000,
	                   "the frame of a scene that moves (animated, cowN, cowNi)"),
	    RS_CLI_U32_OPT("--animate", &o->animate, 0, 1000,
	                   "local frame k shows scene frame --frame + k at FPS a second; 0: still"),
	    CALL("--refine", &o->no_refine, parse_predict, "on|off",
	         "average sub-pixel samples while the pose is still", "on"),
	};
	struct rs_cli cli = {.prog = "raystream-viewer",
	                     .usage = "[options]",
	                     .about = about,
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .render = &desc,
	                     .render_keys = "backend,passes,threads,kernels"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code ? code : -1;
	o->backend = desc.backend;
	o->passes = desc.passes;
	o->threads = desc.threads;
	o->kernels = desc.kernels;
	o->quality = (int)quality;
	o->headless = headless;
	o->verify_local = verify;
	o->start_remote = o->server && !local;
	if (o->verify_local && !o->server)
		return rs_cli_usage_error(&cli, "--verify-local needs --server");
	if ((o->frame || o->animate) && !rs_scenegen_moves(o->scene))
		return rs_cli_usage_error(
		    &cli, "--frame/--animate: scene '%s' does not move (animated, cowN, cowNi)",
		    o->scene);
	if (o->animate && o->verify_local)
		return rs_cli_usage_error(&cli, "--animate and --verify-local: the server's frames "
		                                "move by its own --animate");
	if (o->headless && !o->out_dir && !o->stats && !o->frames && !o->duration_s)
		return rs_cli_usage_error(
		    &cli, "--headless needs --out, --stats, --frames or --duration");
	/* Output targets checked (the folder made) now, so a bad path fails before the run. */
	struct rs_error err = {0};
	if ((o->out_dir && rs_cli_make_dir(o->out_dir, &err) != RS_OK) ||
	    (o->stats && rs_cli_check_output(o->stats, &err) != RS_OK) ||
	    (o->last && rs_cli_check_output(o->last, &err) != RS_OK))
		return rs_cli_fail(&cli, &err);
	return 0;
}

int viewer_main(struct viewer_options *o);

int main(int argc, char **argv)
{
	struct viewer_options o;
	int code = parse_args(argc, argv, &o);
	return code ? (code < 0 ? 0 : code) : viewer_main(&o);
}
