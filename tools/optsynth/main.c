/*
 * raystream-optsynth: what two calibrated cameras see of the handheld's three markers as it
 * follows the simulator's motion script, written as two PNG sequences with the rig file and
 * the true poses, for `raystream-track 'video:...'`; with --bench, the optical path's
 * frame pairs per second and pose error versus centroid noise (markdown). Errors are one
 * line on stderr and a non-zero exit (1 runtime, 2 usage).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_sim.h"
#include "raystream/rs_optical.h"
#include "optsynth.h"
#include "tool_common.h"

#define TOOL "raystream-optsynth"
/* The simulator's default script walks 0.6 m in its first two seconds, out of the
 * cameras' shared view (about 0.5 x 0.4 m at 1 m) for a fifth of the default frames.
 * This one walks a square of 15 cm sides (a quarter turn after each side), with a shake
 * half way: the markers stay in both views for any number of frames. */
#define OPTSYNTH_SCRIPT                                                                            \
	"still:0.25,walk:0.5,turn:1,walk:0.5,turn:1,shake:0.5,walk:0.5,turn:1,walk:0.5,turn:1"

/* The simulator's tracker frame (z up) seen from above: camera 0 looks down its -z from
 * 1 m, so the marker plane (body z up) faces the cameras. */
static void camera_from_tracker(const struct rs_pose *T_tracker_body, struct rs_pose *out)
{
	const struct rs_pose T_cam0_tracker = {.position = {-0.04, -0.03, 1.0},
	                                       .orientation = {1, 0, 0, 0}};
	rs_pose_compose(&T_cam0_tracker, T_tracker_body, out);
}

/* q and -q are one rotation; a canonical (w >= 0) sign flips from frame to frame near
 * 180 degrees (markers facing a camera are about 180 degrees from it), so each written
 * quaternion takes the hemisphere of the one before. */
static void keep_hemisphere(double q[4], const double prev[4])
{
	double dot = q[0] * prev[0] + q[1] * prev[1] + q[2] * prev[2] + q[3] * prev[3];
	if (dot < 0)
		for (int k = 0; k < 4; ++k)
			q[k] = -q[k];
}

/* The simulator's script as a frame source for optsynth_write(). */
struct script_frames {
	struct rs_sim *sim;
};

static int script_frame(void *ctx, const struct optsynth_options *o,
                        const struct rs_optical_rig *rig, const struct rs_pose_layout *L, int i,
                        struct rs_pose *T, uint8_t *img0, uint8_t *img1, struct rs_error *err)
{
	struct script_frames *f = ctx;
	if (i >= o->frames)
		return 0;
	struct rs_marker_sample s;
	struct rs_pose T_tracker_body;
	if (rs_sim_next(f->sim, &s, &T_tracker_body, NULL) != RS_OK)
		return 0;
	camera_from_tracker(&T_tracker_body, T);
	T->time_s = s.host_time_s;
	struct rs_optical_synth_desc d = o->synth;
	d.seed = o->seed * 100003u + (uint64_t)i;
	return rs_optical_synth_render(rig, L, T, &d, img0, img1, err) == RS_OK ? 1 : -1;
}

void optsynth_layout(const struct optsynth_options *o, struct rs_pose_layout *out)
{
	if (o->verifier)
		rs_pose_layout_default_verified(out);
	else
		rs_pose_layout_default(out);
}

/* DIR/layout.json: the layout with its verifier, for the source's layout=FILE (through a
 * temporary file renamed on success). */
static int write_layout(const char *dir, const struct rs_pose_layout *L)
{
	char path[4096], tmp[4200];
	snprintf(path, sizeof path, "%s/layout.json", dir);
	snprintf(tmp, sizeof tmp, "%s.tmp", path);
	FILE *f = fopen(tmp, "w");
	if (!f) {
		fprintf(stderr, TOOL ": cannot write %s\n", path);
		return 0;
	}
	fprintf(f, "{\"markers\": [");
	for (int i = 0; i < 3; ++i)
		fprintf(f, "%s[%.6f, %.6f, %.6f]", i ? ", " : "", L->markers[i][0],
		        L->markers[i][1], L->markers[i][2]);
	fprintf(f, "],\n \"verifier\": [%.6f, %.6f, %.6f]}\n", L->verifier[0], L->verifier[1],
	        L->verifier[2]);
	if (fclose(f) != 0 || rename(tmp, path) != 0) {
		remove(tmp);
		fprintf(stderr, TOOL ": cannot write %s\n", path);
		return 0;
	}
	rs_cli_wrote(path);
	return 1;
}

int optsynth_write(const char *dir, const struct optsynth_options *o, optsynth_frame_fn frame,
                   void *ctx)
{
	struct rs_error err;
	char path[4096], tmp[4200];
	if (rs_cli_make_dir(dir, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		return 1;
	}
	struct rs_optical_rig rig;
	rs_optical_rig_example(o->baseline, o->width, o->height, &rig);
	snprintf(path, sizeof path, "%s/rig.yaml", dir);
	if (rs_optical_rig_save(path, &rig, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		return 1;
	}
	size_t bytes = (size_t)o->width * (size_t)o->height;
	uint8_t *img[2] = {malloc(bytes), malloc(bytes)};
	snprintf(path, sizeof path, "%s/truth.txt", dir);
	snprintf(tmp, sizeof tmp, "%s.tmp", path);
	FILE *truth = fopen(tmp, "w");
	int code = 1, n = 0;
	if (!img[0] || !img[1] || !truth) {
		fprintf(stderr, TOOL ": cannot write %s\n", path);
		goto done;
	}
	struct rs_pose_layout L;
	optsynth_layout(o, &L);
	if (o->verifier && !write_layout(dir, &L))
		goto done;
	fprintf(truth, "# frame time_s T_cam0_markers: x y z (m) qx qy qz qw\n");
	double prev_q[4];
	for (int i = 0;; ++i) {
		struct rs_pose T;
		int got = frame(ctx, o, &rig, &L, i, &T, img[0], img[1], &err);
		if (got < 0) {
			fprintf(stderr, TOOL ": %s\n", err.message);
			goto done;
		}
		if (!got)
			break;
		if (i > 0)
			keep_hemisphere(T.orientation, prev_q);
		memcpy(prev_q, T.orientation, sizeof prev_q);
		for (int v = 0; v < 2; ++v) {
			snprintf(path, sizeof path, "%s/%s_%04d.png", dir, v ? "right" : "left", i);
			if (rs_optical_write_png(path, img[v], o->width, o->height, &err) !=
			    RS_OK) {
				fprintf(stderr, TOOL ": %s\n", err.message);
				goto done;
			}
		}
		fprintf(truth, "%d %.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n", i, T.time_s,
		        T.position[0], T.position[1], T.position[2], T.orientation[0],
		        T.orientation[1], T.orientation[2], T.orientation[3]);
		n++;
	}
	snprintf(path, sizeof path, "%s/truth.txt", dir);
	if (fclose(truth) != 0 || rename(tmp, path) != 0) {
		truth = NULL;
		fprintf(stderr, TOOL ": cannot write %s\n", path);
		goto done;
	}
	truth = NULL;
	snprintf(path, sizeof path, "%s/rig.yaml", dir);
	rs_cli_wrote(path);
	snprintf(path, sizeof path, "%s/truth.txt", dir);
	rs_cli_wrote(path);
	if (o->verifier)
		printf(
		    "%s: %d frame pairs, rig.yaml, layout.json, truth.txt; try\n  raystream-track "
		    "--sigma 1 'video:%s/left_%%04d.png,%s/right_%%04d.png?calib=%s/"
		    "rig.yaml&layout=%s/layout.json&rate=%g'\n",
		    dir, n, dir, dir, dir, dir, o->rate);
	else
		printf("%s: %d frame pairs, rig.yaml, truth.txt; try\n  raystream-track --sigma 1 "
		       "'video:%s/left_%%04d.png,%s/right_%%04d.png?calib=%s/rig.yaml&rate=%g'\n",
		       dir, n, dir, dir, dir, o->rate);
	code = 0;
done:
	if (truth) {
		fclose(truth);
		remove(tmp);
	}
	free(img[0]);
	free(img[1]);
	return code;
}

static int generate(const char *dir, const struct optsynth_options *o)
{
	struct rs_error err;
	/* The script is checked before anything is written: a refused run leaves nothing. */
	struct rs_sim_desc sd = {
	    .seed = o->seed, .rate_hz = o->rate, .script = o->script ? o->script : OPTSYNTH_SCRIPT};
	struct script_frames f = {0};
	if (rs_sim_create(&sd, &f.sim, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		return 2;
	}
	int code = optsynth_write(dir, o, script_frame, &f);
	rs_sim_destroy(&f.sim);
	return code;
}

static enum rs_status parse_size(void *out, const char *v, struct rs_error *err)
{
	struct optsynth_options *o = out;
	uint32_t w, h;
	if (!rs_cli_parse_size(v, 8192, &w, &h) || w < 64 || h < 64)
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not WxH, 64..8192 each", v);
	o->width = (int)w;
	o->height = (int)h;
	return RS_OK;
}

/* --dim/--occlude: marker 0, 1 or 2, stored + 1 (0 means none). */
static enum rs_status parse_marker(void *out, const char *v, struct rs_error *err)
{
	uint32_t id;
	if (!rs_cli_parse_u32(v, 0, 2, &id))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not a marker id 0..2", v);
	*(int *)out = (int)id + 1;
	return RS_OK;
}

static const char about[] =
    "Writes DIR/rig.yaml, DIR/left_%04d.png, DIR/right_%04d.png and DIR/truth.txt (DIR is\n"
    "made) for raystream-track 'video:...'; the default script walks a 15 cm square in\n"
    "view of both cameras (" OPTSYNTH_SCRIPT ").\n"
    "--bench: the optical path's frame pairs per second and pose error against noise\n"
    "(markdown). -n is --frames.\n"
    "--hard NAME: the optical tracker's hard cases as runs with the display out of view\n"
    "for 8 frames between them: edges (a marker's spot walking across each image edge\n"
    "of either camera), corners (a marker at each corner of camera 0), stray (a marker\n"
    "hidden from camera 1 and a marker-like spot on its epipolar line there, 1-45 mm\n"
    "off), ghosts (the display mirrored in a table 10 cm below). --size, --baseline,\n"
    "--noise, --blur, --rate and --seed apply.\n";

int main(int argc, char **argv)
{
	struct optsynth_options o = {
	    .width = 640, .height = 480, .baseline = 0.4, .rate = 60, .synth = {.noise_grey = 2}};
	uint32_t frames = 120, runs = 5;
	double seed = 1;
	bool bench = false, stray = false, reflection = false, verifier = false;
	const char *dir = NULL, *hard = NULL;
	const struct rs_cli_option opts[] = {
	    RS_CLI_U32_OPT("--frames", &frames, 1, 100000, "frame pairs"),
	    RS_CLI_DOUBLE_OPT("--rate", &o.rate, "0.01..10000", 0.01, 1e4, "frame rate, Hz"),
	    {.name = "--script",
	     .kind = RS_CLI_STRING,
	     .out = &o.script,
	     .arg = "S",
	     .help = "simulator motion script (rs_sim.h)",
	     .fallback = "a 15 cm square, below"},
	    {.name = "--size",
	     .kind = RS_CLI_CALL,
	     .out = &o,
	     .call = parse_size,
	     .arg = "WxH",
	     .help = "image size; f = 1.25 W px",
	     .fallback = "640x480"},
	    RS_CLI_DOUBLE_OPT("--baseline", &o.baseline, "0.002..10", 0.002, 10,
	                      "camera distance, m, toed in to meet 1 m ahead"),
	    RS_CLI_DOUBLE_OPT("--noise", &o.synth.noise_grey, "0..100", 0, 100,
	                      "pixel noise, grey levels RMS"),
	    RS_CLI_DOUBLE_OPT("--blur", &o.synth.blur_px, "0..20", 0, 20,
	                      "Gaussian blur sigma, px"),
	    RS_CLI_CALL_OPT("--dim", &o.synth.dim_marker, parse_marker, "0..2",
	                    "marker drawn at half brightness"),
	    RS_CLI_CALL_OPT("--occlude", &o.synth.occluded_marker, parse_marker, "0..2",
	                    "marker hidden from camera 1"),
	    RS_CLI_FLAG_OPT("--stray", &stray, "a stray lamp beside the markers"),
	    RS_CLI_FLAG_OPT("--reflection", &reflection, "a specular streak beside the markers"),
	    RS_CLI_FLAG_OPT("--verifier", &verifier,
	                    "a fourth light on a 12 cm post (rs_pose_layout_default_verified), "
	                    "DIR/layout.json for the source's layout="),
	    RS_CLI_DOUBLE_OPT("--seed", &seed, "0..1e15", 0, 1e15, "noise and motion seed"),
	    {.name = "--hard",
	     .kind = RS_CLI_STRING,
	     .out = &hard,
	     .arg = "NAME",
	     .help = "a hard-case sequence instead of the script: edges, corners, stray, ghosts "
	             "(below)",
	     .fallback = "none"},
	    RS_CLI_FLAG_OPT("--bench", &bench, "benchmark instead of writing frames"),
	    RS_CLI_U32_OPT("--runs", &runs, 1, 64, "--bench: runs per noise level"),
	};
	static const char *const short_names[][2] = {{"-n", "--frames"}};
	rs_tool_long_options(argc, argv, short_names, 1);
	struct rs_cli cli = {
	    .prog = TOOL,
	    .usage = "[options] DIR  |  --hard NAME [options] DIR  |  --bench [--runs N]",
	    .about = about,
	    .options = opts,
	    .option_count = sizeof opts / sizeof opts[0],
	    .positional = &dir,
	    .positional_max = 1,
	    .positional_name = "DIR"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code;
	if (seed != floor(seed))
		return rs_cli_usage_error(&cli, "--seed: '%g' is not a whole number", seed);
	o.frames = (int)frames;
	o.runs = (int)runs;
	o.seed = (uint64_t)seed;
	o.synth.stray_light = stray;
	o.synth.reflection = reflection;
	o.verifier = verifier;
	if (bench && hard)
		return rs_cli_usage_error(&cli, "--bench and --hard exclude each other");
	if (bench)
		return dir ? rs_cli_usage_error(&cli, "--bench writes no files ('%s')", dir)
		           : optsynth_bench(&o);
	if (!dir)
		return rs_cli_usage_error(&cli, "no output folder DIR");
	if (hard) {
		if (!optsynth_hard_known(hard))
			return rs_cli_usage_error(
			    &cli, "--hard: '%s' is not edges, corners, stray or ghosts", hard);
		/* A hard sequence has its own length, motion and disturbances. */
		if (frames != 120 || o.script || stray || reflection || o.synth.dim_marker ||
		    o.synth.occluded_marker)
			return rs_cli_usage_error(&cli,
			                          "--hard %s: --frames, --script, --stray, "
			                          "--reflection, --dim and --occlude do not apply",
			                          hard);
		return optsynth_hard(dir, &o, hard);
	}
	return generate(dir, &o);
}
