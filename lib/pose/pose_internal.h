/* Helpers shared between the pose module's files (private, not installed). */
#ifndef RS_POSE_INTERNAL_H
#define RS_POSE_INTERNAL_H

#include "raystream/rs_pose.h"

/* Side lengths of triangle p (sides[k] is opposite vertex k) and its smallest height
 * (0 for coincident or non-finite points). */
void rs_pose_triangle_metrics(const double p[3][3], double sides[3], double *out_min_height);

/* Smallest absolute difference between any two of the three side lengths. */
double rs_pose_min_side_difference(const double sides[3]);

/* Least over the orderings of b of the largest |a[k] - b[perm k]|: how far two triangles'
 * side lengths are from congruent. */
double rs_pose_side_mismatch(const double a[3], const double b[3]);

/* All orderings of three markers: rs_pose_perms[p][j] = layout id of measured point j. */
extern const int rs_pose_perms[6][3];

/* Index into rs_pose_perms of the ordering whose layout sides fit the measured `sides` (of
 * points `pts`, per-axis noise `sigma`) best. *out_worst: its largest side mismatch (m);
 * *out_separation: how many standard deviations of side-length noise the measurement lies
 * from the nearest other ordering's decision boundary (label.c). */
int rs_pose_label(const double layout_sides[3], const double pts[3][3], const double sides[3],
                  double sigma, double *out_worst, double *out_separation);

/* Linearised RMS errors of a pose solved from three markers with per-axis noise sigma: the
 * rotation angle (sigma sqrt(trace J^-1)) and the 3-D position of the display origin. */
void rs_pose_error_law(const struct rs_pose_layout *layout, double sigma, double *out_rot_rms,
                       double *out_pos_rms);

#endif
