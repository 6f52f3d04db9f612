/* Simulator internals shared by sim.c and sim_motion.c: script segments and the motion
 * each one prescribes, plus the few quaternion helpers the integration needs. */
#ifndef RS_SIM_INTERNAL_H
#define RS_SIM_INTERNAL_H

#include <stddef.h>

#include "raystream/rs_sim.h"

enum sim_segment_kind { SIM_STILL, SIM_WALK, SIM_TURN, SIM_SHAKE };

struct sim_segment {
	enum sim_segment_kind kind;
	double duration_s;
};

struct sim_motion {
	double v_world[3]; /* linear velocity, tracker frame, m/s */
	double w_world[3]; /* angular velocity about tracker axes, rad/s */
	double w_body[3];  /* angular velocity about body axes, rad/s */
};

/* Parse "walk:2,still,turn:1.5"; at most RS_SIM_MAX_SEGMENTS segments. */
enum rs_status sim_parse_script(const char *script, struct sim_segment *out, size_t *out_n,
                                struct rs_error *err);

/* Velocities of `seg` at `t` seconds into it, for the current orientation `q`. */
void sim_segment_motion(const struct sim_segment *seg, double t, const double q[4],
                        struct sim_motion *out);

/* q <- exp(w_world h / 2) * q * exp(w_body h / 2), renormalised. */
void sim_quat_integrate(double q[4], const double w_world[3], const double w_body[3], double h);

#endif
