/* raystream-server internals: options, viewer slots, the render threads and the poll loop.
 * One mutex guards everything both sides touch (a viewer's pose, its pending frame and
 * counters); sockets belong to the poll thread only. */
#ifndef RS_SERVER_H
#define RS_SERVER_H

#include "app_pace.h"
#include <pthread.h>
#include <stdint.h>

#include "raystream/rs_codec.h"
#include "raystream/rs_render.h"
#include "raystream/rs_stream.h"

#define SERVER_MAX_VIEWERS 64
#define SERVER_MAX_THREADS 16
/* Connections that have not said HELLO live in their own small pool, at most a few per
 * address, so idle ones cannot take the slots of viewers (greet.c). */
#define SERVER_MAX_GREETING 16
#define SERVER_GREETING_PER_ADDRESS 4
#define SERVER_SLOTS (SERVER_MAX_VIEWERS + SERVER_MAX_GREETING)

struct server_options {
	const char *scene, *backend, *bind, *token, *port_file, *stats;
	uint16_t port;
	uint32_t width, height, passes, lights, threads, render_threads, max_viewers;
	enum rs_shadow_mode shadows;
	uint32_t shadow_map_size, shadow_filter; /* --shadows map:RES:FILTER (0: default) */
	enum rs_kernel_stage kernels;            /* --kernels: fragment passes or compute */
	int quality;                             /* default JPEG quality */
	int raw;                                 /* send raw RGBA8 instead of JPEG */
	enum rs_jpeg_subsampling sub;            /* 4:2:0 or 4:4:4 */
	double link_mbps, link_latency_ms;
	double read_timeout_s; /* slow drip / no hello */
	double stale_s;        /* a pending frame older than this is dropped for a newer pose */
	double duration_s;     /* 0: until SIGINT/SIGTERM */
	/* --animate FPS: a scene that moves plays at FPS frames a second from --frame (frame =
	 * frame + elapsed * FPS, each frame the pure function of its number that
	 * raystream-render --frame renders); 0: the still --frame */
	uint32_t animate, frame;
	double target_fps; /* per viewer dynamic resolution (app_pace); 0: off */
};

/* A frame buffer: one whole FRAME message. */
struct outframe {
	uint8_t *data;
	size_t len, off, cap;
	double ready_s, queued_s;
	int full;
};

struct viewer {
	int active, fd, hello_done, closing;
	int acks;      /* the viewer acknowledges frames (RS_STREAM_POSE_ACKS): pace by them */
	int refine;    /* it wants still cameras refined (RS_STREAM_POSE_REFINE) */
	uint32_t addr; /* the peer's IPv4 address, for the greeting pool */
	uint32_t id;
	char peer[64];
	int quality;
	double connected_s, msg_start_s, last_stats_s;
	struct rs_stream_parser parser;
	uint8_t inbuf[RS_STREAM_HEADER_SIZE + RS_STREAM_MAX_CLIENT_PAYLOAD];
	/* guarded by server.lock */
	struct rs_stream_pose pose;
	int pose_new, busy;
	uint32_t next_frame_id;
	struct outframe pending;
	uint64_t poses, poses_replaced, frames_rendered, frames_dropped;
	/* still-pose refinement: a POSE with the camera of the one before (the viewer holds
	 * its resting pose's camera while still) renders the next sub-pixel sample into the
	 * float mean, which is what gets encoded (JPEG once, of the mean) */
	struct rs_camera refine_cam;
	uint32_t refine_sample;
	int refine_have, refine_level;
	/* --target-fps: this viewer's render scale, from its frames' render + encode times */
	struct app_pace pace;
	float *refine_acc; /* the mean; taken by the render thread while busy */
	struct outframe inflight;
	uint8_t ctl[1024];
	size_t ctl_len, ctl_off;
	int sending_ctl;
	struct rs_stream_link link;
	uint64_t frames_sent, bytes_sent;
	struct rs_stream_stats reported; /* the viewer's last STATS */
};

struct server {
	struct server_options o;
	const struct rs_scene *scene;
	size_t frame_cap;    /* bytes of one FRAME message at most */
	const char *backend; /* the backend opened ("auto" resolved) */
	pthread_mutex_t lock;
	pthread_cond_t work;
	int stop;
	int wake[2]; /* render threads -> poll loop */
	struct viewer viewers[SERVER_SLOTS];
	uint32_t next_viewer_id;
	uint64_t frames_rendered, disconnects;
	uint32_t scene_frame; /* --animate: the newest scene frame a render thread showed */
	double render_ms_sum;
	double started_s;
};

/* Render threads (render.c): each its own renderer and JPEG encoder. */
int server_render_start(struct server *s, pthread_t *threads, uint32_t n);
void server_render_stop(struct server *s, pthread_t *threads, uint32_t n);

/* Viewer input (net.c): read and handle what arrived; queue a whole control message
 * (0 on success); close with a BYE (best effort) and a logged reason. */
void server_viewer_read(struct server *s, struct viewer *v, double now);
int server_viewer_queue(struct viewer *v, const struct rs_stream_msg *m);
void server_viewer_close(struct server *s, struct viewer *v, uint32_t reason, const char *why);
/* The camera a POSE asks for, at the server's image size. */
void server_pose_camera(const struct server *s, const struct rs_stream_pose *p,
                        struct rs_camera *cam);

/* Admission (greet.c): a slot in the greeting pool for a new connection, evicting the
 * oldest greeting one of the same address (or of the busiest address) when the pool is
 * full; NULL when none is free. On HELLO, server_viewer_promote() counts the viewer
 * against --max-viewers and gives it frame buffers (0 on success, else a BYE was sent). */
struct viewer *server_greeting_slot(struct server *s, uint32_t addr, double now);
int server_viewer_promote(struct server *s, struct viewer *v);

/* The poll loop (loop.c): returns when stopped or the duration ran out; 0 on success. */
int server_run(struct server *s, int listen_fd);

/* One log line on stderr, prefixed with the program name and seconds since start. */
void server_log(const struct server *s, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

double server_now_s(void);

#endif
