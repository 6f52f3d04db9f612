/*
 * raystream-optsynth --hard NAME: the optical tracker's hard cases (issue 19) as frame
 * sequences a user can track with raystream-track 'video:...', the same files as the
 * default sequence. Each sequence is a series of runs; between runs the display is out of
 * view for 8 frames (0.13 s at 60 Hz), so each run starts without a temporal prior.
 *   edges    a marker's spot walking from 4 px beyond to 8 px inside each edge of
 *            either camera (8 runs of 13 frames)
 *   corners  a marker at each corner of camera 0, 3 px outside to 8 px inside (4 x 12)
 *   stray    a marker hidden from camera 1 and a stray spot of a marker's size and
 *            brightness on its epipolar line there, 1 to 45 mm along camera 0's ray, on
 *            either side, after 5 clean frames (6 runs of 28 frames)
 *   ghosts   the display mirrored in a glossy table 10 cm below camera 0 (a dimmer
 *            congruent triple), from the first frame or after 5 clean ones (6 x 12)
 * The example rig has no lens distortion: positions are placed by pinhole projection.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_optical.h"
#include "raystream/rs_pose.h"
#include "optsynth.h"

#define TOOL "raystream-optsynth"
#define GAP_FRAMES 8 /* out of view between runs: longer than the tracker's 0.1 s prior */
#define MAX_SPOTS 3

struct hard_frame {
	struct rs_pose T;
	int occluded;                  /* 1 + marker hidden from camera 1 (0: none) */
	int spots;                     /* extra spots, drawn in both views where not NaN */
	double spot[MAX_SPOTS][2][2];  /* [spot][view][x y] */
	double spot_sigma, spot_level; /* their Gaussian shape */
};

struct hard_plan {
	struct hard_frame *f;
	int n, cap;
	uint64_t rng;
};

static struct hard_frame *plan_add(struct hard_plan *p)
{
	if (p->n == p->cap) {
		int cap = p->cap ? 2 * p->cap : 256;
		struct hard_frame *f = realloc(p->f, (size_t)cap * sizeof *f);
		if (!f)
			return NULL;
		p->f = f;
		p->cap = cap;
	}
	struct hard_frame *f = &p->f[p->n++];
	memset(f, 0, sizeof *f);
	f->T.orientation[3] = 1;
	return f;
}

/* The display out of both views (5 m to the side). */
static int plan_gap(struct hard_plan *p)
{
	for (int i = 0; i < GAP_FRAMES; ++i) {
		struct hard_frame *f = plan_add(p);
		if (!f)
			return 0;
		f->T.position[0] = 5.0;
		f->T.position[2] = 1.0;
	}
	return 1;
}

static double uniform01(struct hard_plan *p)
{
	p->rng ^= p->rng << 13;
	p->rng ^= p->rng >> 7;
	p->rng ^= p->rng << 17;
	return (double)(p->rng >> 11) * (1.0 / 9007199254740992.0);
}

static double gauss(struct hard_plan *p)
{
	double u = uniform01(p), v = uniform01(p);
	return sqrt(-2.0 * log(u > 1e-300 ? u : 1e-300)) * cos(2.0 * RS_PI * v);
}

static void quat_mul(const double a[4], const double b[4], double out[4])
{
	out[0] = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
	out[1] = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
	out[2] = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
	out[3] = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
}

/* The display about 1 m in front of camera 0, facing the rig within ~35 degrees, any turn
 * about its normal. */
static void facing_pose(struct hard_plan *p, struct rs_pose *T)
{
	double ax = gauss(p), ay = gauss(p), n = hypot(ax, ay);
	double ang = 0.6 * (2.0 * uniform01(p) - 1.0), turn = RS_PI * uniform01(p);
	double qa[4] = {sin(ang / 2) * ax / n, sin(ang / 2) * ay / n, 0, cos(ang / 2)};
	double qz[4] = {0, 0, sin(turn / 2), cos(turn / 2)}, q[4];
	quat_mul(qa, qz, q);
	memset(T, 0, sizeof *T);
	memcpy(T->orientation, q, sizeof q);
	T->position[0] = -0.04 + 0.05 * (2 * uniform01(p) - 1);
	T->position[1] = -0.03 + 0.05 * (2 * uniform01(p) - 1);
	T->position[2] = 1.0 + 0.05 * (2 * uniform01(p) - 1);
}

/* Pinhole projection of X (camera-0 frame) into camera v. */
static void project(const struct rs_optical_rig *rig, int v, const double X0[3], double *u,
                    double *w)
{
	double X[3] = {X0[0], X0[1], X0[2]};
	if (v) {
		const double *R = rig->R_cam1_cam0, *t = rig->t_cam1_cam0;
		for (int i = 0; i < 3; ++i)
			X[i] =
			    R[3 * i] * X0[0] + R[3 * i + 1] * X0[1] + R[3 * i + 2] * X0[2] + t[i];
	}
	const double *K = rig->cam[v].K;
	*u = K[0] * X[0] / X[2] + K[2];
	*w = K[4] * X[1] / X[2] + K[5];
}

/* The display turned by q with marker m 1 m deep on camera v's ray through pixel (u, w). */
static void place(const struct rs_optical_rig *rig, const struct rs_pose_layout *L, int v, int m,
                  const double q[4], double u, double w, struct rs_pose *T)
{
	const double *K = rig->cam[v].K;
	double Xv[3] = {(u - K[2]) / K[0], (w - K[5]) / K[4], 1.0}, X0[3];
	if (v) { /* x0 = R^T (x1 - t) */
		const double *R = rig->R_cam1_cam0, *t = rig->t_cam1_cam0;
		for (int i = 0; i < 3; ++i)
			X0[i] = R[i] * (Xv[0] - t[0]) + R[3 + i] * (Xv[1] - t[1]) +
			        R[6 + i] * (Xv[2] - t[2]);
	} else {
		memcpy(X0, Xv, sizeof X0);
	}
	memset(T, 0, sizeof *T);
	memcpy(T->orientation, q, 4 * sizeof(double));
	double mr[3];
	rs_pose_transform_point(T, L->markers[m], mr);
	for (int k = 0; k < 3; ++k)
		T->position[k] = X0[k] - mr[k];
}

static int plan_edges(struct hard_plan *p, const struct rs_optical_rig *rig,
                      const struct rs_pose_layout *L, int W, int H)
{
	static const double id[4] = {0, 0, 0, 1};
	static const int marker[4] = {0, 1, 0, 2}; /* outermost at left, right, top, bottom */
	double s = W / 640.0;
	for (int v = 0; v < 2; ++v)
		for (int e = 0; e < 4; ++e) {
			if (!plan_gap(p))
				return 0;
			for (double off = -4; off <= 8; off += 1) {
				double u = W / 2.0 - 40 * s, w = H / 2.0 - 30 * s;
				if (e == 0)
					u = off;
				else if (e == 1)
					u = W - 1 - off;
				else if (e == 2)
					w = off;
				else
					w = H - 1 - off;
				struct hard_frame *f = plan_add(p);
				if (!f)
					return 0;
				place(rig, L, v, marker[e], id, u, w, &f->T);
			}
		}
	return 1;
}

static int plan_corners(struct hard_plan *p, const struct rs_optical_rig *rig,
                        const struct rs_pose_layout *L, int W, int H)
{
	static const double id[4] = {0, 0, 0, 1}, half[4] = {0, 0, 1, 0};
	static const struct {
		const double *q;
		int m, right, bottom;
	} c[4] = {{id, 0, 0, 0}, {id, 1, 1, 0}, {half, 1, 0, 1}, {half, 0, 1, 1}};
	for (int k = 0; k < 4; ++k) {
		if (!plan_gap(p))
			return 0;
		for (double off = -3; off <= 8; off += 1) {
			struct hard_frame *f = plan_add(p);
			if (!f)
				return 0;
			place(rig, L, 0, c[k].m, c[k].q, c[k].right ? W - 1 - off : off,
			      c[k].bottom ? H - 1 - off : off, &f->T);
		}
	}
	return 1;
}

static int plan_stray(struct hard_plan *p, const struct rs_optical_rig *rig,
                      const struct rs_pose_layout *L, int W)
{
	for (int trial = 0; trial < 3; ++trial) {
		struct rs_pose T;
		facing_pose(p, &T);
		int k = trial; /* each marker hidden once */
		double X[3];
		rs_pose_transform_point(&T, L->markers[k], X);
		double n = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
		for (int sign = -1; sign <= 1; sign += 2) {
			if (!plan_gap(p))
				return 0;
			for (int i = 0; i < 5; ++i) {
				struct hard_frame *f = plan_add(p);
				if (!f)
					return 0;
				f->T = T;
			}
			for (double d = 0.001; d <= 0.0451; d += 0.002) {
				struct hard_frame *f = plan_add(p);
				if (!f)
					return 0;
				f->T = T;
				f->occluded = k + 1;
				double G[3];
				for (int c = 0; c < 3; ++c)
					G[c] = X[c] * (1 + sign * d / n);
				f->spots = 1;
				f->spot[0][0][0] = f->spot[0][0][1] = NAN;
				project(rig, 1, G, &f->spot[0][1][0], &f->spot[0][1][1]);
				/* a marker's spot: a 3.2 px disc at 230 grey at 640 px */
				f->spot_sigma = 2.4 * W / 640.0;
				f->spot_level = 240;
			}
		}
	}
	return 1;
}

static int plan_ghosts(struct hard_plan *p, const struct rs_optical_rig *rig,
                       const struct rs_pose_layout *L, int W)
{
	for (int trial = 0; trial < 6; ++trial) {
		struct rs_pose T;
		facing_pose(p, &T);
		if (!plan_gap(p))
			return 0;
		for (int i = 0; i < 12; ++i) {
			struct hard_frame *f = plan_add(p);
			if (!f)
				return 0;
			f->T = T;
			if (trial % 2 && i < 5)
				continue; /* the reflection appears after five clean frames */
			f->spots = 3;
			f->spot_sigma = 1.6 * W / 640.0;
			f->spot_level = 150;
			for (int m = 0; m < 3; ++m) {
				double X[3];
				rs_pose_transform_point(&T, L->markers[m], X);
				X[1] = 2 * 0.1 - X[1]; /* mirrored in the plane y = 0.1 m */
				for (int v = 0; v < 2; ++v)
					project(rig, v, X, &f->spot[m][v][0], &f->spot[m][v][1]);
			}
		}
	}
	return 1;
}

static void add_spot(uint8_t *img, int W, int H, double cx, double cy, double sigma, double level)
{
	int r = (int)ceil(4 * sigma);
	for (int y = (int)floor(cy) - r; y <= (int)floor(cy) + r; ++y)
		for (int x = (int)floor(cx) - r; x <= (int)floor(cx) + r; ++x) {
			if (x < 0 || y < 0 || x >= W || y >= H)
				continue;
			double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
			double v = img[(size_t)y * W + x] + level * exp(-d2 / (2 * sigma * sigma));
			img[(size_t)y * W + x] = (uint8_t)(v > 255 ? 255 : v);
		}
}

static int hard_frame(void *ctx, const struct optsynth_options *o, const struct rs_optical_rig *rig,
                      const struct rs_pose_layout *L, int i, struct rs_pose *T, uint8_t *img0,
                      uint8_t *img1, struct rs_error *err)
{
	const struct hard_plan *p = ctx;
	if (i >= p->n)
		return 0;
	const struct hard_frame *f = &p->f[i];
	struct rs_optical_synth_desc d = o->synth;
	d.seed = o->seed * 100003u + (uint64_t)i;
	d.occluded_marker = f->occluded;
	if (rs_optical_synth_render(rig, L, &f->T, &d, img0, img1, err) != RS_OK)
		return -1;
	uint8_t *img[2] = {img0, img1};
	for (int s = 0; s < f->spots; ++s)
		for (int v = 0; v < 2; ++v)
			if (!isnan(f->spot[s][v][0]))
				add_spot(img[v], o->width, o->height, f->spot[s][v][0],
				         f->spot[s][v][1], f->spot_sigma, f->spot_level);
	*T = f->T;
	T->time_s = i / o->rate;
	return 1;
}

static const char *const hard_names[] = {"edges", "corners", "stray", "ghosts"};

int optsynth_hard_known(const char *name)
{
	for (size_t k = 0; k < sizeof hard_names / sizeof hard_names[0]; ++k)
		if (!strcmp(name, hard_names[k]))
			return 1;
	return 0;
}

int optsynth_hard(const char *dir, const struct optsynth_options *o, const char *name)
{
	struct rs_optical_rig rig;
	rs_optical_rig_example(o->baseline, o->width, o->height, &rig);
	struct rs_pose_layout L;
	optsynth_layout(o, &L);
	struct hard_plan p = {.rng = o->seed * 2654435761u + 1919};
	int ok;
	if (!strcmp(name, "edges"))
		ok = plan_edges(&p, &rig, &L, o->width, o->height);
	else if (!strcmp(name, "corners"))
		ok = plan_corners(&p, &rig, &L, o->width, o->height);
	else if (!strcmp(name, "stray"))
		ok = plan_stray(&p, &rig, &L, o->width);
	else
		ok = plan_ghosts(&p, &rig, &L, o->width);
	int code = 1;
	if (!ok)
		fprintf(stderr, TOOL ": --hard %s: out of memory\n", name);
	else
		code = optsynth_write(dir, o, hard_frame, &p);
	free(p.f);
	return code;
}
