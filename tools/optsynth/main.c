/*
 * raystream-optsynth: what two calibrated cameras see of the handheld's three markers as it
 * follows the simulator's motion script, written as two PNG sequences with the rig file and
 * the true poses, for `raystream-track 'video:...'`; with --bench, the optical path's
 * frame pairs per second and pose error versus centroid noise (markdown). Errors are one
 * line on stderr and a non-zero exit (1 runtime, 2 usage).
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "raystream/rs_sim.h"
#include "raystream/rs_optical.h"
#include "optsynth.h"

#define TOOL "raystream-optsynth"
/* The simulator's default script walks 0.6 m in its first two seconds, out of the
 * cameras' shared view (about 0.5 x 0.4 m at 1 m) for a fifth of the default frames.
 * This one walks a square of 15 cm sides (a quarter turn after each side), with a shake
 * half way: the markers stay in both views for any number of frames. */
#define OPTSYNTH_SCRIPT                                                                            \
	"still:0.25,walk:0.5,turn:1,walk:0.5,turn:1,shake:0.5,walk:0.5,turn:1,walk:0.5,turn:1"

static void usage(FILE *f)
{
	fprintf(f,
	        "usage: " TOOL " [options] DIR      DIR/rig.yaml, DIR/left_%%04d.png,\n"
	        "                                         DIR/right_%%04d.png, DIR/truth.txt\n"
	        "       " TOOL " --bench [--runs N]\n"
	        "  -n, --frames N    frame pairs (default 120)\n"
	        "  --rate HZ         frame rate of the motion (default 60)\n"
	        "  --script S        simulator motion script (default, in view throughout:\n"
	        "                    " OPTSYNTH_SCRIPT ")\n"
	        "  --size WxH        image size (default 640x480; f = 1.25 W px)\n"
	        "  --baseline M      camera distance (default 0.4 m), toed in to meet 1 m ahead\n"
	        "  --noise G         pixel noise, grey levels RMS (default 2)\n"
	        "  --blur PX         Gaussian blur sigma (default 0)\n"
	        "  --dim ID          marker ID drawn at half brightness\n"
	        "  --occlude ID      marker ID hidden from camera 1\n"
	        "  --stray           a stray lamp beside the markers\n"
	        "  --reflection      a specular streak beside the markers\n"
	        "  --seed N          noise and motion seed (default 1)\n");
}

static int die_usage(const char *msg, const char *arg)
{
	fprintf(stderr, TOOL ": error: %s%s%s (try --help)\n", msg, arg ? ": " : "",
	        arg ? arg : "");
	return 2;
}

static int num(const char *s, double lo, double hi, double *out)
{
	char *end = NULL;
	errno = 0;
	double v = strtod(s, &end);
	if (!s[0] || *end || errno || !(v >= lo && v <= hi))
		return 0;
	*out = v;
	return 1;
}

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

static int generate(const char *dir, const struct optsynth_options *o)
{
	struct rs_error err;
	char path[4096], tmp[4200];
	/* The script is checked before anything is written: a refused run leaves nothing. */
	struct rs_sim_desc sd = {
	    .seed = o->seed, .rate_hz = o->rate, .script = o->script ? o->script : OPTSYNTH_SCRIPT};
	struct rs_sim *sim = NULL;
	if (rs_sim_create(&sd, &sim, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		return 2;
	}
	if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
		fprintf(stderr, TOOL ": cannot create %s: %s\n", dir, strerror(errno));
		rs_sim_destroy(&sim);
		return 1;
	}
	struct rs_optical_rig rig;
	rs_optical_rig_example(o->baseline, o->width, o->height, &rig);
	snprintf(path, sizeof path, "%s/rig.yaml", dir);
	if (rs_optical_rig_save(path, &rig, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		rs_sim_destroy(&sim);
		return 1;
	}
	size_t bytes = (size_t)o->width * (size_t)o->height;
	uint8_t *img[2] = {malloc(bytes), malloc(bytes)};
	snprintf(path, sizeof path, "%s/truth.txt", dir);
	snprintf(tmp, sizeof tmp, "%s.tmp", path);
	FILE *truth = fopen(tmp, "w");
	int code = 1;
	if (!img[0] || !img[1] || !truth) {
		fprintf(stderr, TOOL ": cannot write %s\n", path);
		goto done;
	}
	struct rs_pose_layout L;
	rs_pose_layout_default(&L);
	fprintf(truth, "# frame time_s T_cam0_markers: x y z (m) qx qy qz qw\n");
	double prev_q[4];
	for (int i = 0; i < o->frames; ++i) {
		struct rs_marker_sample s;
		struct rs_pose T_tracker_body, T;
		if (rs_sim_next(sim, &s, &T_tracker_body, NULL) != RS_OK)
			break;
		camera_from_tracker(&T_tracker_body, &T);
		if (i > 0)
			keep_hemisphere(T.orientation, prev_q);
		memcpy(prev_q, T.orientation, sizeof prev_q);
		struct rs_optical_synth_desc d = o->synth;
		d.seed = o->seed * 100003u + (uint64_t)i;
		if (rs_optical_synth_render(&rig, &L, &T, &d, img[0], img[1], &err) != RS_OK) {
			fprintf(stderr, TOOL ": %s\n", err.message);
			goto done;
		}
		for (int v = 0; v < 2; ++v) {
			snprintf(path, sizeof path, "%s/%s_%04d.png", dir, v ? "right" : "left", i);
			if (rs_optical_write_png(path, img[v], o->width, o->height, &err) !=
			    RS_OK) {
				fprintf(stderr, TOOL ": %s\n", err.message);
				goto done;
			}
		}
		fprintf(truth, "%d %.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n", i, s.host_time_s,
		        T.position[0], T.position[1], T.position[2], T.orientation[0],
		        T.orientation[1], T.orientation[2], T.orientation[3]);
	}
	snprintf(path, sizeof path, "%s/truth.txt", dir);
	if (fclose(truth) != 0 || rename(tmp, path) != 0) {
		truth = NULL;
		fprintf(stderr, TOOL ": cannot write %s\n", path);
		goto done;
	}
	truth = NULL;
	printf("%s: %d frame pairs, rig.yaml, truth.txt; try\n  raystream-track --sigma 1 "
	       "'video:%s/left_%%04d.png,%s/right_%%04d.png?calib=%s/rig.yaml&rate=%g'\n",
	       dir, o->frames, dir, dir, dir, o->rate);
	code = 0;
done:
	if (truth) {
		fclose(truth);
		remove(tmp);
	}
	free(img[0]);
	free(img[1]);
	rs_sim_destroy(&sim);
	return code;
}

int main(int argc, char **argv)
{
	struct optsynth_options o = {.frames = 120,
	                             .rate = 60,
	                             .width = 640,
	                             .height = 480,
	                             .baseline = 0.4,
	                             .seed = 1,
	                             .runs = 5,
	                             .synth = {.noise_grey = 2}};
	const char *dir = NULL;
	int bench = 0;
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		double d;
		int flag = !strcmp(a, "--stray") || !strcmp(a, "--reflection") ||
		           !strcmp(a, "--bench") || !strcmp(a, "-h") || !strcmp(a, "--help");
		if (a[0] == '-' && a[1] && !flag && !v)
			return die_usage("missing value for", a);
		if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
			usage(stdout);
			return 0;
		} else if (!strcmp(a, "--bench")) {
			bench = 1;
			continue;
		} else if (!strcmp(a, "--stray")) {
			o.synth.stray_light = 1;
			continue;
		} else if (!strcmp(a, "--reflection")) {
			o.synth.reflection = 1;
			continue;
		} else if (!strcmp(a, "-n") || !strcmp(a, "--frames")) {
			if (!num(v, 1, 100000, &d) || d != floor(d))
				return die_usage("frames must be 1 to 100000", v);
			o.frames = (int)d;
		} else if (!strcmp(a, "--runs")) {
			if (!num(v, 1, 64, &d) || d != floor(d))
				return die_usage("runs must be 1 to 64", v);
			o.runs = (int)d;
		} else if (!strcmp(a, "--rate")) {
			if (!num(v, 0.01, 1e4, &o.rate))
				return die_usage("rate must be 0.01 to 10000 Hz", v);
		} else if (!strcmp(a, "--script")) {
			o.script = v;
		} else if (!strcmp(a, "--size")) {
			char extra;
			if (sscanf(v, "%dx%d%c", &o.width, &o.height, &extra) != 2 ||
			    o.width < 64 || o.height < 64 || o.width > 8192 || o.height > 8192)
				return die_usage("size must be WxH, 64 to 8192 each", v);
		} else if (!strcmp(a, "--baseline")) {
			if (!num(v, 0.002, 10, &o.baseline))
				return die_usage("baseline must be 0.002 to 10 m", v);
		} else if (!strcmp(a, "--noise")) {
			if (!num(v, 0, 100, &o.synth.noise_grey))
				return die_usage("noise must be 0 to 100 grey levels", v);
		} else if (!strcmp(a, "--blur")) {
			if (!num(v, 0, 20, &o.synth.blur_px))
				return die_usage("blur must be 0 to 20 px", v);
		} else if (!strcmp(a, "--dim") || !strcmp(a, "--occlude")) {
			if (!num(v, 0, 2, &d) || d != floor(d))
				return die_usage("marker id must be 0, 1 or 2", v);
			*(!strcmp(a, "--dim") ? &o.synth.dim_marker : &o.synth.occluded_marker) =
			    (int)d + 1;
		} else if (!strcmp(a, "--seed")) {
			if (!num(v, 0, 1e15, &d) || d != floor(d))
				return die_usage("seed must be a whole number", v);
			o.seed = (uint64_t)d;
		} else if (a[0] == '-' && a[1]) {
			return die_usage("unknown option", a);
		} else if (!dir) {
			dir = a;
			continue;
		} else {
			return die_usage("more than one directory", a);
		}
		++i;
	}
	if (bench)
		return dir ? die_usage("--bench writes no files", dir) : optsynth_bench(&o);
	if (!dir)
		return die_usage("no output directory", NULL);
	return generate(dir, &o);
}
