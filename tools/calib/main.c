/*
 * raystream-calib: calibrate a stereo camera pair from checkerboard frame pairs (two image
 * sequences or videos, frame i of each taken together) and write the rig file the video:
 * and cam: sources read. --synth writes synthetic checkerboard pairs of a known rig to try
 * it. Errors are one line on stderr and a non-zero exit (1 runtime, 2 usage).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "raystream/rs_optical.h"
#include "tool_common.h"

#define TOOL "raystream-calib"

static void usage(FILE *f)
{
	fprintf(f, "usage: " TOOL " [options] LEFT RIGHT\n"
	           "       " TOOL " --synth DIR [--views N]\n"
	           "  LEFT, RIGHT      image sequences (left_%%04d.png, from 0) or video files\n"
	           "  -o, --out FILE   rig file to write, .yaml/.yml/.json (default rig.yaml)\n"
	           "  --board CxR      inner corners of the checkerboard (default 9x6)\n"
	           "  --square M       square side in metres (default 0.025)\n"
	           "  --max N          use at most N frame pairs (default 100)\n"
	           "  --synth DIR      write N synthetic pairs DIR/left_%%04d.png,\n"
	           "                   DIR/right_%%04d.png and their rig DIR/true.yaml\n"
	           "  --views N        synthetic pairs (default 16)\n");
}

static int die_usage(const char *msg, const char *arg)
{
	fprintf(stderr, TOOL ": error: %s%s%s (try --help)\n", msg, arg ? ": " : "",
	        arg ? arg : "");
	return 2;
}

static int synth(const char *dir, int views, const struct rs_optical_board *b)
{
	struct rs_optical_rig rig;
	rs_optical_rig_example(0.4, 640, 480, &rig);
	struct rs_error err;
	char path[4096];
	if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
		fprintf(stderr, TOOL ": cannot create %s: %s\n", dir, strerror(errno));
		return 1;
	}
	snprintf(path, sizeof path, "%s/true.yaml", dir);
	if (rs_optical_rig_save(path, &rig, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		return 1;
	}
	static uint8_t img[2][640 * 480];
	uint64_t s = 8;
	int n = 0;
	for (int tries = 0; n < views && tries < 100 * views; ++tries) {
		/* a small deterministic generator: positions and tilts across the view */
		double u[5];
		for (int k = 0; k < 5; ++k) {
			s = s * 6364136223846793005ull + 1442695040888963407ull;
			u[k] = (double)(s >> 11) / 9007199254740992.0;
		}
		double ax = 0.45 * (2 * u[0] - 1), ay = 0.45 * (2 * u[1] - 1);
		struct rs_pose T = {
		    .position = {-0.1 + 0.2 * (2 * u[2] - 1), -0.06 + 0.14 * (2 * u[3] - 1),
		                 0.9 + 0.15 * u[4]},
		    .orientation = {sin(ax / 2) * cos(ay / 2), cos(ax / 2) * sin(ay / 2),
		                    -sin(ax / 2) * sin(ay / 2), cos(ax / 2) * cos(ay / 2)}};
		if (rs_optical_synth_board(&rig, b, &T, img[0], img[1], NULL) != RS_OK)
			continue;
		for (int v = 0; v < 2; ++v) {
			snprintf(path, sizeof path, "%s/%s_%04d.png", dir, v ? "right" : "left", n);
			if (rs_optical_write_png(path, img[v], 640, 480, &err) != RS_OK) {
				fprintf(stderr, TOOL ": %s\n", err.message);
				return 1;
			}
		}
		++n;
	}
	printf("wrote %d checkerboard pairs and %s/true.yaml\n", n, dir);
	return 0;
}

static int calibrate(const char *left, const char *right, const char *out, int max,
                     const struct rs_optical_board *b)
{
	struct rs_error err;
	struct rs_optical_frames *f[2] = {NULL, NULL};
	struct rs_optical_image *views[2] = {calloc((size_t)max, sizeof **views),
	                                     calloc((size_t)max, sizeof **views)};
	int code = 1, n = 0;
	if (!views[0] || !views[1]) {
		fprintf(stderr, TOOL ": out of memory\n");
		goto done;
	}
	if (rs_optical_frames_open(left, 0, &f[0], &err) != RS_OK ||
	    rs_optical_frames_open(right, 0, &f[1], &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		goto done;
	}
	for (; n < max; ++n) {
		struct rs_optical_image im[2];
		enum rs_status st[2];
		for (int v = 0; v < 2; ++v)
			st[v] = rs_optical_frames_read(f[v], &im[v], &err);
		if (st[0] == RS_END || st[1] == RS_END)
			break;
		if (st[0] != RS_OK || st[1] != RS_OK) {
			fprintf(stderr, TOOL ": %s\n", err.message);
			goto done;
		}
		/* the streams own their frames until the next read: keep copies */
		for (int v = 0; v < 2; ++v) {
			size_t bytes = (size_t)im[v].width * (size_t)im[v].height;
			uint8_t *copy = malloc(bytes);
			if (!copy) {
				fprintf(stderr, TOOL ": out of memory\n");
				goto done;
			}
			for (int y = 0; y < im[v].height; ++y)
				memcpy(copy + (size_t)y * (size_t)im[v].width,
				       im[v].pixels + (size_t)y * im[v].stride,
				       (size_t)im[v].width);
			views[v][n] = (struct rs_optical_image){copy, im[v].width, im[v].height,
			                                        (size_t)im[v].width};
		}
	}
	struct rs_optical_rig rig;
	size_t used = 0;
	if (rs_optical_calibrate(b, views[0], views[1], (size_t)n, &rig, &used, &err) != RS_OK ||
	    rs_optical_rig_save(out, &rig, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		goto done;
	}
	double *t = rig.t_cam1_cam0;
	printf("%s: %zu of %d pairs used, reprojection RMS %.3f px, f %.1f/%.1f px, baseline "
	       "%.4f m\n",
	       out, used, n, rig.rms_px, rig.cam[0].K[0], rig.cam[1].K[0],
	       sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]));
	code = 0;
done:
	for (int v = 0; v < 2; ++v) {
		for (int i = 0; views[v] && i < n; ++i)
			free((void *)views[v][i].pixels);
		free(views[v]);
		rs_optical_frames_destroy(&f[v]);
	}
	return code;
}

int main(int argc, char **argv)
{
	const char *out = "rig.yaml", *synth_dir = NULL, *files[2] = {NULL, NULL};
	struct rs_optical_board b = {.cols = 9, .rows = 6, .square_m = 0.025};
	int max = 100, views = 16, nfiles = 0;
	for (int i = 1; i < argc; ++i) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
			usage(stdout);
			return 0;
		}
		int takes = !strcmp(a, "-o") || !strcmp(a, "--out") || !strcmp(a, "--board") ||
		            !strcmp(a, "--square") || !strcmp(a, "--max") ||
		            !strcmp(a, "--synth") || !strcmp(a, "--views");
		if (takes && !v)
			return die_usage("missing value for", a);
		if (!strcmp(a, "-o") || !strcmp(a, "--out")) {
			out = v;
		} else if (!strcmp(a, "--board")) {
			char extra;
			if (sscanf(v, "%dx%d%c", &b.cols, &b.rows, &extra) != 2 || b.cols < 3 ||
			    b.rows < 3 || b.cols > 64 || b.rows > 64)
				return die_usage("board must be CxR inner corners, 3 to 64 each",
				                 v);
		} else if (!strcmp(a, "--square")) {
			char *end = NULL;
			b.square_m = strtod(v, &end);
			if (*end || !(b.square_m > 0 && b.square_m < 10))
				return die_usage("square must be 0 to 10 m", v);
		} else if (!strcmp(a, "--max")) {
			uint32_t n;
			if (!rs_tool_parse_u32(v, 5, 10000, &n))
				return die_usage("max must be 5 to 10000", v);
			max = (int)n;
		} else if (!strcmp(a, "--views")) {
			uint32_t n;
			if (!rs_tool_parse_u32(v, 1, 1000, &n))
				return die_usage("views must be 1 to 1000", v);
			views = (int)n;
		} else if (!strcmp(a, "--synth")) {
			synth_dir = v;
		} else if (a[0] == '-' && a[1]) {
			return die_usage("unknown option", a);
		} else if (nfiles < 2) {
			files[nfiles++] = a;
			continue;
		} else {
			return die_usage("more than two streams", a);
		}
		++i;
	}
	if (synth_dir)
		return nfiles ? die_usage("--synth takes no streams", files[0])
		              : synth(synth_dir, views, &b);
	if (nfiles != 2)
		return die_usage("need LEFT and RIGHT streams", NULL);
	return calibrate(files[0], files[1], out, max, &b);
}
