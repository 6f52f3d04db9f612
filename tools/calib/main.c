/*
 * raystream-calib: calibrate a stereo camera pair from checkerboard frame pairs (two image
 * sequences or videos, frame i of each taken together) and write the rig file the video:
 * and cam: sources read. --synth writes synthetic checkerboard pairs of a known rig to try
 * it. Errors are one line on stderr and a non-zero exit (1 runtime, 2 usage).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_cli.h"
#include "raystream/rs_optical.h"
#include "tool_common.h"

#define TOOL "raystream-calib"

static int synth(const char *dir, int views, const struct rs_optical_board *b)
{
	struct rs_optical_rig rig;
	rs_optical_rig_example(0.4, 640, 480, &rig);
	struct rs_error err;
	char path[4096];
	if (rs_cli_make_dir(dir, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
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
	rs_cli_wrote(out);
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

static enum rs_status parse_board(void *out, const char *v, struct rs_error *err)
{
	struct rs_optical_board *b = out;
	char extra;
	int c, r;
	if (sscanf(v, "%dx%d%c", &c, &r, &extra) != 2 || c < 3 || r < 3 || c > 64 || r > 64)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "'%s' is not CxR inner corners, 3..64 each", v);
	b->cols = c;
	b->rows = r;
	return RS_OK;
}

static const char about[] =
    "LEFT, RIGHT: image sequences (left_%04d.png, from 0) or video files, frame i of each\n"
    "taken together. --synth DIR writes synthetic pairs of a known rig (DIR/left_%04d.png,\n"
    "DIR/right_%04d.png, DIR/true.yaml; DIR is made) to try it. -o is --out.\n";

int main(int argc, char **argv)
{
	const char *out = "rig.yaml", *synth_dir = NULL, *files[2] = {NULL, NULL};
	struct rs_optical_board b = {.cols = 9, .rows = 6, .square_m = 0.025};
	uint32_t max = 100, views = 16;
	const struct rs_cli_option opts[] = {
	    RS_CLI_STRING_OPT("--out", &out, "FILE", "rig file to write: .yaml, .yml or .json"),
	    {.name = "--board",
	     .kind = RS_CLI_CALL,
	     .out = &b,
	     .call = parse_board,
	     .arg = "CxR",
	     .help = "inner corners of the checkerboard",
	     .fallback = "9x6"},
	    RS_CLI_DOUBLE_OPT("--square", &b.square_m, "M", 1e-6, 10, "square side, metres"),
	    RS_CLI_U32_OPT("--max", &max, 5, 10000, "use at most N frame pairs"),
	    RS_CLI_STRING_OPT("--synth", &synth_dir, "DIR", "write synthetic pairs instead"),
	    RS_CLI_U32_OPT("--views", &views, 1, 1000, "--synth: pairs"),
	};
	static const char *const short_names[][2] = {{"-o", "--out"}};
	rs_tool_long_options(argc, argv, short_names, 1);
	struct rs_cli cli = {.prog = TOOL,
	                     .usage = "[options] LEFT RIGHT  |  --synth DIR [--views N]",
	                     .about = about,
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .positional = files,
	                     .positional_max = 2,
	                     .positional_name = "LEFT RIGHT"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code;
	if (synth_dir)
		return cli.positional_count
		           ? rs_cli_usage_error(&cli, "--synth takes no streams ('%s')", files[0])
		           : synth(synth_dir, (int)views, &b);
	if (cli.positional_count != 2)
		return rs_cli_usage_error(&cli, "need LEFT and RIGHT streams");
	return calibrate(files[0], files[1], out, (int)max, &b);
}
