/* Private to rs_trace: per-ray values of the triangle tests computed once per ray rather
 * than once per triangle (the watertight test's shear, the parallel-test scale), used by
 * traverse.c. rs_intersect_triangle() is the same code with a one-off preparation. */
#ifndef RS_TRACE_INTERSECT_INTERNAL_H
#define RS_TRACE_INTERSECT_INTERNAL_H

#include "raystream/rs_trace.h"

struct rs__ray_pre {
	const struct rs_ray *ray; /* tmin/tmax are read from here at each test */
	double dir_max;           /* max |dir component| */
	int kx, ky, kz;           /* watertight: dominant axis kz, winding-preserving kx, ky */
	double sx, sy, sz;        /* watertight shear */
	/* Watertight: edge functions down to -edge_slack * (|u| + |v| + |w|) count as inside.
	 * 0 (rs__ray_prepare) in one level, where neighbours see the same ray; the two-level
	 * walk sets RS__INSTANCE_EDGE_SLACK, as each instance sees its own rounding of it. */
	double edge_slack;
};

/* Relative slack of the two-level walk's edge tests: well above the double rounding of a ray
 * taken through a transform (~1e-16 times the condition and the offset), well below float
 * vertex rounding (6e-8), so a shared edge or corner between instances never lets a ray
 * through and no visible sliver is added (docs/tracer.md, "Instances"). */
#define RS__INSTANCE_EDGE_SLACK 1e-9

void rs__ray_prepare(const struct rs_ray *ray, struct rs__ray_pre *out);

/* As rs_intersect_triangle() but accepting tmin < t <= tmax (closed at tmax, so that an
 * equally distant triangle can still win the tie-break). */
bool rs__intersect_triangle_pre(enum rs_triangle_test test, const double v0[3], const double v1[3],
                                const double v2[3], const struct rs__ray_pre *pre, double *out_t,
                                double *out_u, double *out_v);

/* rs_trace_closest()/rs_trace_occluded() for a ray already in the packed frame (R1). */
bool rs__trace_closest_local(const struct rs_packed *packed, enum rs_triangle_test test,
                             const struct rs_ray *ray, struct rs_hit *out_hit,
                             struct rs_trace_counters *counters);
bool rs__trace_occluded_local(const struct rs_packed *packed, enum rs_triangle_test test,
                              const struct rs_ray *ray, struct rs_trace_counters *counters);

#endif
