/* The display's marker layout: the built-in example, the JSON calibration file and the
 * check that makes swapped marker ids recoverable (a scalene, non-degenerate triangle). */
#include "raystream/rs_pose.h"

#include "pose_internal.h"
#include "private/rs_vec.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void rs_pose_layout_default(struct rs_pose_layout *out_layout)
{
	static const struct rs_pose_layout def = {
	    .markers = {{0.0, 0.0, 0.0}, {0.10, 0.0, 0.0}, {0.02, 0.08, 0.0}},
	    .T_markers_display = {.orientation = {0.0, 0.0, 0.0, 1.0}},
	};
	*out_layout = def;
}

void rs_pose_layout_default_verified(struct rs_pose_layout *out_layout)
{
	rs_pose_layout_default(out_layout);
	out_layout->verifier[0] = 0.04;
	out_layout->verifier[1] = 0.03;
	out_layout->verifier[2] = 0.12;
	out_layout->has_verifier = 1;
}

void rs_pose_triangle_metrics(const double p[3][3], double sides[3], double *out_min_height)
{
	/* sides[k] is the side opposite vertex k, i.e. between the other two. */
	double e[3][3];
	rs_v3_sub(p[2], p[1], e[0]);
	rs_v3_sub(p[0], p[2], e[1]);
	rs_v3_sub(p[1], p[0], e[2]);
	double longest = 0.0;
	for (int k = 0; k < 3; ++k) {
		sides[k] = rs_v3_norm(e[k]);
		if (sides[k] > longest)
			longest = sides[k];
	}
	/* The smallest height stands on the longest side; use the cross product of the two
	 * shorter edges' vectors, which is the same for any pair (twice the area). */
	double c[3];
	rs_v3_cross(e[1], e[2], c);
	double twice_area = rs_v3_norm(c);
	*out_min_height = longest > 0.0 && isfinite(twice_area) ? twice_area / longest : 0.0;
}

/* The verifier: finite, off every side's line (a turn about that side moves it) and never
 * a corner of a triangle that fits the layout's sides. */
static enum rs_status check_verifier(const struct rs_pose_layout *layout, const double sides[3],
                                     struct rs_error *err)
{
	const double *v = layout->verifier;
	if (!rs_v3_finite(v) ||
	    !(fabs(v[0]) <= RS_POSE_MAX_COORD_M && fabs(v[1]) <= RS_POSE_MAX_COORD_M &&
	      fabs(v[2]) <= RS_POSE_MAX_COORD_M))
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "layout: the verifier has a non-finite or huge coordinate");
	for (int k = 0; k < 3; ++k) {
		const double *a = layout->markers[(k + 1) % 3], *b = layout->markers[(k + 2) % 3];
		double t[3][3], ts[3], h, ab[3], av[3], c[3];
		memcpy(t[0], a, sizeof t[0]);
		memcpy(t[1], b, sizeof t[1]);
		memcpy(t[2], v, sizeof t[2]);
		rs_pose_triangle_metrics((const double(*)[3])t, ts, &h);
		/* distance from the line a-b: |(b - a) x (v - a)| / |b - a| (|b - a| > 0: the
		 * triangle's heights were checked) */
		rs_v3_sub(b, a, ab);
		rs_v3_sub(v, a, av);
		rs_v3_cross(ab, av, c);
		double line = rs_v3_norm(c) / rs_v3_norm(ab);
		if (!(line >= RS_POSE_LAYOUT_MIN_VERIFIER_M))
			return rs_error_set(
			    err, RS_ERR_DEGENERATE,
			    "layout: the verifier is %.4f m from the line of markers "
			    "%d and %d (< %.4f m): a turn about it would not move it",
			    line, (k + 1) % 3, (k + 2) % 3, RS_POSE_LAYOUT_MIN_VERIFIER_M);
		double mismatch = rs_pose_side_mismatch(ts, sides);
		if (!(mismatch >= RS_POSE_LAYOUT_MIN_VERIFIER_M))
			return rs_error_set(
			    err, RS_ERR_DEGENERATE,
			    "layout: the verifier and markers %d and %d make a triangle "
			    "within %.4f m of the layout's sides (< %.4f m): it could be "
			    "taken for a marker",
			    (k + 1) % 3, (k + 2) % 3, mismatch, RS_POSE_LAYOUT_MIN_VERIFIER_M);
	}
	return RS_OK;
}

enum rs_status rs_pose_layout_check(const struct rs_pose_layout *layout, struct rs_error *err)
{
	RS_ASSERT(layout);
	for (int i = 0; i < RS_TRACK_MARKERS; ++i)
		if (!rs_v3_finite(layout->markers[i]) ||
		    !(fabs(layout->markers[i][0]) <= RS_POSE_MAX_COORD_M &&
		      fabs(layout->markers[i][1]) <= RS_POSE_MAX_COORD_M &&
		      fabs(layout->markers[i][2]) <= RS_POSE_MAX_COORD_M))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "layout: marker %d has a non-finite or huge coordinate",
			                    i);
	const struct rs_pose *T = &layout->T_markers_display;
	if (!rs_v3_finite(T->position) || fabs(T->position[0]) > RS_POSE_MAX_COORD_M ||
	    fabs(T->position[1]) > RS_POSE_MAX_COORD_M ||
	    fabs(T->position[2]) > RS_POSE_MAX_COORD_M || !isfinite(T->orientation[0]) ||
	    !isfinite(T->orientation[1]) || !isfinite(T->orientation[2]) ||
	    !isfinite(T->orientation[3]))
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "layout: non-finite or huge T_markers_display");
	double qn = sqrt(rs_q_dot(T->orientation, T->orientation));
	/* All zero is a zero-initialised struct: identity, like every zero default. */
	if (qn != 0.0 && fabs(qn - 1.0) > 1e-6)
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "layout: T_markers_display quaternion not unit (norm %g)", qn);
	double sides[3], h;
	rs_pose_triangle_metrics(layout->markers, sides, &h);
	if (!(h > RS_POSE_LAYOUT_MIN_HEIGHT_M))
		return rs_error_set(err, RS_ERR_DEGENERATE,
		                    "layout: smallest triangle height %.4f m <= %.4f m", h,
		                    RS_POSE_LAYOUT_MIN_HEIGHT_M);
	double diff = rs_pose_min_side_difference(sides);
	if (!(diff > RS_POSE_LAYOUT_MIN_SIDE_DIFF_M))
		return rs_error_set(err, RS_ERR_DEGENERATE,
		                    "layout: not scalene (two sides differ by %.4f m <= %.4f m), "
		                    "swapped ids could not be told apart",
		                    diff, RS_POSE_LAYOUT_MIN_SIDE_DIFF_M);
	return layout->has_verifier ? check_verifier(layout, sides, err) : RS_OK;
}

/* Least over the six orderings of the largest difference between the sides of a and b. */
double rs_pose_side_mismatch(const double a[3], const double b[3])
{
	double best = INFINITY;
	for (int p = 0; p < 6; ++p) {
		double worst = 0.0;
		for (int k = 0; k < 3; ++k) {
			double d = fabs(a[k] - b[rs_pose_perms[p][k]]);
			worst = d > worst ? d : worst;
		}
		best = worst < best ? worst : best;
	}
	return best;
}

double rs_pose_min_side_difference(const double sides[3])
{
	double d01 = fabs(sides[0] - sides[1]), d12 = fabs(sides[1] - sides[2]),
	       d02 = fabs(sides[0] - sides[2]);
	double m = d01 < d12 ? d01 : d12;
	return m < d02 ? m : d02;
}

static int json_vec(const cJSON *arr, int n, double *out)
{
	if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) != n)
		return 0;
	for (int i = 0; i < n; ++i) {
		const cJSON *v = cJSON_GetArrayItem(arr, i);
		if (!cJSON_IsNumber(v))
			return 0;
		out[i] = v->valuedouble;
	}
	return 1;
}

/* Whole file into a NUL-terminated heap buffer (calibration files are small). */
static enum rs_status read_file(const char *path, char **out_text, struct rs_error *err)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return rs_error_set(err, errno == ENOENT ? RS_ERR_NOT_FOUND : RS_ERR_IO,
		                    "layout: cannot open '%s'", path);
	enum { MAX_SIZE = 1 << 20 };
	char *text = malloc(MAX_SIZE + 1);
	if (!text) {
		fclose(f);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "layout: out of memory");
	}
	size_t len = fread(text, 1, MAX_SIZE + 1, f);
	int failed = ferror(f);
	fclose(f);
	if (failed || len > MAX_SIZE) {
		free(text);
		return rs_error_set(err, failed ? RS_ERR_IO : RS_ERR_LIMIT,
		                    "layout: cannot read '%s' (error or larger than 1 MiB)", path);
	}
	text[len] = '\0';
	*out_text = text;
	return RS_OK;
}

enum rs_status rs_pose_layout_load(const char *path, struct rs_pose_layout *out_layout,
                                   struct rs_error *err)
{
	RS_ASSERT(path && out_layout);
	char *text = NULL;
	enum rs_status st = read_file(path, &text, err);
	if (st != RS_OK)
		return st;
	cJSON *root = cJSON_Parse(text);
	free(text);
	if (!root)
		return rs_error_set(err, RS_ERR_PARSE, "layout: '%s' is not valid JSON", path);
	struct rs_pose_layout l;
	memset(&l, 0, sizeof l);
	l.T_markers_display.orientation[3] = 1.0;
	const cJSON *markers = cJSON_GetObjectItemCaseSensitive(root, "markers");
	if (!cJSON_IsArray(markers) || cJSON_GetArraySize(markers) != RS_TRACK_MARKERS) {
		cJSON_Delete(root);
		return rs_error_set(err, RS_ERR_PARSE,
		                    "layout: '%s': \"markers\" must be 3 [x,y,z]", path);
	}
	for (int i = 0; i < RS_TRACK_MARKERS; ++i) {
		if (!json_vec(cJSON_GetArrayItem(markers, i), 3, l.markers[i])) {
			cJSON_Delete(root);
			return rs_error_set(err, RS_ERR_PARSE,
			                    "layout: '%s': marker %d is not [x,y,z]", path, i);
		}
	}
	const cJSON *cal = cJSON_GetObjectItemCaseSensitive(root, "T_markers_display");
	if (cal) {
		const cJSON *pos = cJSON_GetObjectItemCaseSensitive(cal, "position");
		const cJSON *ori = cJSON_GetObjectItemCaseSensitive(cal, "orientation");
		if (!cJSON_IsObject(cal) || !json_vec(pos, 3, l.T_markers_display.position) ||
		    !json_vec(ori, 4, l.T_markers_display.orientation)) {
			cJSON_Delete(root);
			return rs_error_set(
			    err, RS_ERR_PARSE,
			    "layout: '%s': T_markers_display needs position [x,y,z] "
			    "and orientation [x,y,z,w]",
			    path);
		}
	}
	const cJSON *ver = cJSON_GetObjectItemCaseSensitive(root, "verifier");
	if (ver) {
		if (!json_vec(ver, 3, l.verifier)) {
			cJSON_Delete(root);
			return rs_error_set(err, RS_ERR_PARSE,
			                    "layout: '%s': \"verifier\" must be [x,y,z]", path);
		}
		l.has_verifier = 1;
	}
	cJSON_Delete(root);
	double *q = l.T_markers_display.orientation;
	if (!rs_q_normalize(q, q))
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "layout: '%s': zero or non-finite calibration quaternion",
		                    path);
	rs_q_canonical(q);
	st = rs_pose_layout_check(&l, err);
	if (st != RS_OK)
		return st;
	*out_layout = l;
	return RS_OK;
}
