/* Helpers shared between the pose module's files (private, not installed). */
#ifndef RS_POSE_INTERNAL_H
#define RS_POSE_INTERNAL_H

/* Side lengths of triangle p (sides[k] is opposite vertex k) and its smallest height
 * (0 for coincident or non-finite points). */
void rs_pose_triangle_metrics(const double p[3][3], double sides[3], double *out_min_height);

/* Smallest absolute difference between any two of the three side lengths. */
double rs_pose_min_side_difference(const double sides[3]);

#endif
