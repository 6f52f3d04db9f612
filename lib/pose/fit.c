/* Closed-form absolute orientation (Horn 1987, "Closed-form solution of absolute orientation
 * using unit quaternions"), double precision. With three points the centred cross-covariance
 * has rank <= 2, so SVD-based fits that "flip if det(H) < 0" pick the sign from noise; Horn's
 * quaternion is a proper rotation by construction and needs no such rule. */
#include "raystream/rs_pose.h"

#include "private/rs_vec.h"

#include <float.h>

/* Eigen-decomposition of a symmetric 4x4 matrix by cyclic Jacobi rotations: robust for
 * repeated eigenvalues (which is exactly the degenerate case we must detect), and cheap. */
static void jacobi4(double a[4][4], double vec[4][4], double val[4])
{
	for (int i = 0; i < 4; ++i)
		for (int j = 0; j < 4; ++j)
			vec[i][j] = i == j ? 1.0 : 0.0;
	for (int sweep = 0; sweep < 32; ++sweep) {
		double off = 0.0, diag = 0.0;
		for (int i = 0; i < 4; ++i) {
			diag += a[i][i] * a[i][i];
			for (int j = i + 1; j < 4; ++j)
				off += a[i][j] * a[i][j];
		}
		if (off <= 1e-32 * diag)
			break;
		for (int p = 0; p < 3; ++p) {
			for (int q = p + 1; q < 4; ++q) {
				double apq = a[p][q];
				if (apq == 0.0)
					continue;
				double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
				double t = (theta >= 0.0 ? 1.0 : -1.0) /
				           (fabs(theta) + sqrt(theta * theta + 1.0));
				double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
				for (int k = 0; k < 4; ++k) {
					double akp = a[k][p], akq = a[k][q];
					a[k][p] = c * akp - s * akq;
					a[k][q] = s * akp + c * akq;
				}
				for (int k = 0; k < 4; ++k) {
					double apk = a[p][k], aqk = a[q][k];
					a[p][k] = c * apk - s * aqk;
					a[q][k] = s * apk + c * aqk;
				}
				/* Exact zero, as the rotation was chosen to make it (keeps the
				 * convergence test from chasing rounding noise). */
				a[p][q] = a[q][p] = 0.0;
				for (int k = 0; k < 4; ++k) {
					double vkp = vec[k][p], vkq = vec[k][q];
					vec[k][p] = c * vkp - s * vkq;
					vec[k][q] = s * vkp + c * vkq;
				}
			}
		}
	}
	for (int i = 0; i < 4; ++i)
		val[i] = a[i][i];
}

static enum rs_status fit_fail(struct rs_pose *out_T, double *out_rms, struct rs_error *err,
                               enum rs_status st, const char *msg)
{
	if (out_T) {
		memset(out_T, 0, sizeof *out_T);
		out_T->orientation[3] = 1.0;
	}
	if (out_rms)
		*out_rms = 0.0;
	return rs_error_set(err, st, "rs_pose_fit: %s", msg);
}

enum rs_status rs_pose_fit(const double (*model)[3], const double (*measured)[3], size_t n,
                           struct rs_pose *out_T, double *out_rms, struct rs_error *err)
{
	RS_ASSERT(model && measured && out_T);
	if (n < 3)
		return fit_fail(out_T, out_rms, err, RS_ERR_INVALID, "need at least 3 points");
	for (size_t i = 0; i < n; ++i) {
		for (int k = 0; k < 3; ++k) {
			if (!(fabs(model[i][k]) <= RS_POSE_MAX_COORD_M) ||
			    !(fabs(measured[i][k]) <= RS_POSE_MAX_COORD_M))
				return fit_fail(out_T, out_rms, err, RS_ERR_BAD_DATA,
				                "non-finite or out-of-range coordinate");
		}
	}
	/* Centroids first, then covariance of the centred points: accumulating raw products of
	 * coordinates 10 km from the origin would cancel away every digit of a 0.1 mm signal. */
	double cm[3] = {0}, cd[3] = {0};
	for (size_t i = 0; i < n; ++i)
		for (int k = 0; k < 3; ++k) {
			cm[k] += model[i][k];
			cd[k] += measured[i][k];
		}
	for (int k = 0; k < 3; ++k) {
		cm[k] /= (double)n;
		cd[k] /= (double)n;
	}
	double S[3][3] = {{0}}, ssm = 0.0, ssd = 0.0;
	for (size_t i = 0; i < n; ++i) {
		double m[3], d[3];
		rs_v3_sub(model[i], cm, m);
		rs_v3_sub(measured[i], cd, d);
		ssm += rs_v3_dot(m, m);
		ssd += rs_v3_dot(d, d);
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				S[a][b] += m[a] * d[b];
	}
	if (!(ssm > 0.0) || !(ssd > 0.0))
		return fit_fail(out_T, out_rms, err, RS_ERR_DEGENERATE, "coincident points");
	/* Horn's N in (w, x, y, z) order; its top eigenvector is the rotation model -> measured. */
	double sxx = S[0][0], sxy = S[0][1], sxz = S[0][2], syx = S[1][0], syy = S[1][1],
	       syz = S[1][2], szx = S[2][0], szy = S[2][1], szz = S[2][2];
	double N[4][4] = {
	    {sxx + syy + szz, syz - szy, szx - sxz, sxy - syx},
	    {syz - szy, sxx - syy - szz, sxy + syx, szx + sxz},
	    {szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy},
	    {sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz},
	};
	double V[4][4], ev[4];
	jacobi4(N, V, ev);
	int best = 0;
	for (int i = 1; i < 4; ++i)
		if (ev[i] > ev[best])
			best = i;
	double second = -INFINITY;
	for (int i = 0; i < 4; ++i)
		if (i != best && ev[i] > second)
			second = ev[i];
	/* Collinear points leave rotation about their line free: the top eigenvalue is double.
	 * The gap is 2 * (second moment about the weaker in-plane axis) for exact data, so
	 * compare it with the spread sqrt(ssm * ssd). */
	double scale = sqrt(ssm * ssd);
	if (!(ev[best] - second > 1e-9 * scale))
		return fit_fail(out_T, out_rms, err, RS_ERR_DEGENERATE,
		                "points (nearly) collinear: rotation undetermined");
	double q[4] = {V[1][best], V[2][best], V[3][best], V[0][best]};
	if (!rs_q_normalize(q, q))
		return fit_fail(out_T, out_rms, err, RS_ERR_DEGENERATE, "no rotation found");
	rs_q_canonical(q);
	double rcm[3];
	rs_q_rotate(q, cm, rcm);
	out_T->time_s = 0.0;
	for (int k = 0; k < 3; ++k)
		out_T->position[k] = cd[k] - rcm[k];
	memcpy(out_T->orientation, q, sizeof q);
	if (out_rms) {
		/* Residuals from centred coordinates too, so far-away points do not cancel. */
		double sum = 0.0;
		for (size_t i = 0; i < n; ++i) {
			double m[3], d[3], rm[3], r[3];
			rs_v3_sub(model[i], cm, m);
			rs_v3_sub(measured[i], cd, d);
			rs_q_rotate(q, m, rm);
			rs_v3_sub(rm, d, r);
			sum += rs_v3_dot(r, r);
		}
		*out_rms = sqrt(sum / (double)n);
	}
	return RS_OK;
}

void rs_pose_compose(const struct rs_pose *T_a_b, const struct rs_pose *T_b_c, struct rs_pose *out)
{
	double p[3], q[4];
	double t = T_b_c->time_s;
	rs_q_rotate(T_a_b->orientation, T_b_c->position, p);
	for (int k = 0; k < 3; ++k)
		p[k] += T_a_b->position[k];
	rs_q_mul(T_a_b->orientation, T_b_c->orientation, q);
	rs_q_normalize(q, q);
	rs_q_canonical(q);
	out->time_s = t;
	memcpy(out->position, p, sizeof p);
	memcpy(out->orientation, q, sizeof q);
}

void rs_pose_transform_point(const struct rs_pose *T, const double p[3], double out[3])
{
	double r[3];
	rs_q_rotate(T->orientation, p, r);
	for (int k = 0; k < 3; ++k)
		out[k] = r[k] + T->position[k];
}

double rs_pose_angle_between(const struct rs_pose *a, const struct rs_pose *b)
{
	double ac[4], d[4], v[3];
	rs_q_conj(a->orientation, ac);
	rs_q_mul(b->orientation, ac, d);
	rs_q_log(d, v);
	return rs_v3_norm(v);
}
