/* raystream-viewer internals: options, the session state, the remote link and outputs. */
#ifndef RS_VIEWER_H
#define RS_VIEWER_H

#include <stdint.h>

#include "app_pace.h"
#include "app_refine.h"

#include "raystream/rs_codec.h"
#include "raystream/rs_pose.h"
#include "raystream/rs_render.h"
#include "raystream/rs_stream.h"
#include "raystream/rs_track.h"
#include "raystream/rs_view.h"

struct rs_window;

struct viewer_options {
	const char *tracker, *server, *scene, *backend, *token, *out_dir, *stats, *layout, *last;
	uint32_t width, height, passes, threads, every, frames, pose_id_base;
	int quality, headless, verify_local, start_remote;
	int readback;      /* --present readback: GPU frames read back and uploaded (benchmarks) */
	int no_predict;    /* --predict off: cameras from the newest pose as sampled */
	int no_refine;     /* --refine off: no still-pose refinement */
	double target_fps; /* --target-fps: dynamic resolution in the window (0: off) */
	int fixed_level;   /* --render-scale: that level of app_pace_scales, else -1 */
	double duration_s, linger_s;
	struct rs_view_calibration cal;
	/* --frame N: the frame of a scene that moves; --animate FPS: local frame k shows scene
	 * frame N + k at FPS frames a second of scene time (0: still) */
	uint32_t frame, animate;
	enum rs_kernel_stage kernels; /* --kernels: the GL backends' stage for local frames */
};

/* Latency samples kept for the median and 99th percentile. */
#define VIEWER_MAX_SAMPLES 65536
/* Recent cameras by pose id, for --verify-local. */
#define VIEWER_POSE_RING 512

struct viewer_link {
	int fd;
	struct rs_stream_parser parser;
	uint8_t *inbuf;
	uint8_t out[RS_STREAM_HEADER_SIZE + 128]; /* the newest unsent pose (latest wins) */
	size_t out_len, out_off;
	/* frame acknowledgements (RS_STREAM_POSE_ACKS): a STATS after each frame received */
	uint8_t ack[RS_STREAM_HEADER_SIZE + 32];
	size_t ack_len, ack_off;
	uint32_t frames_in, frames_acked;
	uint32_t viewer_id;
	uint64_t bytes_in;
	struct rs_stream_stats server_stats; /* last STATS from the server */
};

struct viewer {
	struct viewer_options o;
	struct rs_scene *scene;
	struct rs_track_source *tracker;
	struct rs_pose_solver *solver;
	/* pose prediction to display time: the filter's constant-velocity prediction (pass
	 * through, no smoothing) over the measured latency, capped at 30 ms */
	struct rs_pose_filter *filter;
	double latency_avg_ms, predicted_ms_sum;
	uint64_t predicted_n;
	struct rs_view *view;
	struct rs_renderer *local; /* local rendering and --verify-local */
	struct rs_jpeg *jpeg;
	struct viewer_link link;
	struct rs_window *window; /* NULL when headless */
	int remote;               /* showing remote frames (else local) */
	int direct;               /* v->local draws into the window itself (no readback) */
	int shown;                /* the local path already showed this frame (direct/scaled) */
	/* dynamic resolution (local.c): renderers at the smaller scales, opened when first
	 * needed (level 0 is v->local), the controller and the scaled frame's bytes */
	struct rs_renderer *ladder[APP_PACE_LEVELS];
	uint32_t scene_frame; /* the frame of v->scene (--frame, --animate) */
	int ladder_direct[APP_PACE_LEVELS];
	struct app_pace pace;
	uint8_t *small;
	/* still-pose refinement (local frames): the pose the newest camera came from */
	struct app_refine refine;
	struct rs_pose pose_now;
	/* remote: the camera sent is held the same while still (the server then refines),
	 * and the samples in the newest frame */
	struct app_refine refine_remote;
	uint32_t remote_samples;
	double remote_scale; /* the newest remote frame's width over the window's */
	double remote_scale_min;
	uint8_t *rgba, *check;   /* the frame shown; a local render to compare with */
	uint32_t pose_id;        /* last pose id sent or rendered */
	struct rs_camera camera; /* current camera */
	enum rs_view_state view_state;
	struct rs_camera ring[VIEWER_POSE_RING];
	uint32_t ring_id[VIEWER_POSE_RING];
	/* measurements */
	uint64_t frames, frames_written, gaps, order_errors, unknown_poses;
	uint32_t last_frame_id, last_pose_id_shown;
	int have_frame;
	double *latency_ms;
	uint64_t latency_n;
	double psnr_min, psnr_sum;
	uint64_t psnr_n;
	double started_s, last_line_s;
	uint64_t frames_at_line, bytes_at_line, latency_at_line;
};

/* Remote link (remote.c). */
int viewer_connect(struct viewer *v);
void viewer_send_pose(struct viewer *v, const struct rs_camera *cam, uint32_t flags);
/* Flush the pending pose and read what arrived; calls viewer_show() for each frame.
 * Returns 0, or -1 when the connection ended (reason printed). */
int viewer_pump(struct viewer *v, int timeout_ms);
void viewer_disconnect(struct viewer *v, const char *why);

/* Outputs (output.c). */
void viewer_show(struct viewer *v, uint32_t frame_id, uint32_t pose_id, uint64_t pose_time_us);
int viewer_write_stats(struct viewer *v);
void viewer_status_line(struct viewer *v, double now, int force);
/* Write the frame shown last to `path` (temp + rename); 0 on success. */
int viewer_write_last(struct viewer *v, const char *path);

/* The window (window.c, through backends/window when built). */
enum viewer_key { VIEWER_KEY_NONE, VIEWER_KEY_QUIT, VIEWER_KEY_SWITCH, VIEWER_KEY_RECENTRE };
int viewer_window_open(struct viewer *v);
/* A GLES renderer on the window's own context (frames drawn straight into it); 0 on
 * success, else -1 with the reason in err. */
int viewer_window_renderer(struct viewer *v, const struct rs_render_desc *desc,
                           struct rs_renderer **out, struct rs_error *err);
/* Show an RGBA8 image of any size up to the window's, scaled to fill it. */
void viewer_window_present_image(struct viewer *v, const uint8_t *rgba, uint32_t w, uint32_t h);

/* Local rendering (local.c): open v->local (0 on success), render the current camera at the
 * frame-rate target's scale and show it, close every renderer. */
int viewer_local_open(struct viewer *v);
void viewer_local_frame(struct viewer *v);
void viewer_local_close(struct viewer *v);
void viewer_window_present(struct viewer *v);
void viewer_window_caption(struct viewer *v, const char *text);
enum viewer_key viewer_window_poll(struct viewer *v);
void viewer_window_close(struct viewer *v);

double viewer_now_s(void);

#endif
