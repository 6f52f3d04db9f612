/**
 * @file rs_optical.h
 * Optical marker tracking with two calibrated cameras (backends/opencv; the paper's PPT):
 * stereo rig calibration and its file, bright-blob detection with sub-pixel centroids,
 * epipolar matching, triangulation and labelling of the three markers, and a synthetic
 * frame generator for tests. OpenCV (C++) stays inside the backend; this header is C.
 *
 * Frames: the tracker frame is camera 0's (x right, y down, z forward, metres).
 * T_cam1_cam0 maps camera-0 points into camera 1 (OpenCV's stereoCalibrate R, T).
 * Images are 8-bit grey, caller-owned, row stride in bytes.
 */
#ifndef RS_OPTICAL_H
#define RS_OPTICAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "raystream/rs_pose.h"
#include "raystream/rs_status.h"
#include "raystream/rs_track.h"
#include "raystream/rs_track_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Pinhole camera with OpenCV's 5-term distortion (k1 k2 p1 p2 k3). */
struct rs_optical_camera {
	int width, height; /**< image size in pixels */
	double K[9];       /**< row-major [fx 0 cx; 0 fy cy; 0 0 1] */
	double dist[5];    /**< k1 k2 p1 p2 k3 */
};

/** A calibrated stereo pair. */
struct rs_optical_rig {
	struct rs_optical_camera cam[2];
	double R_cam1_cam0[9]; /**< row-major rotation: x1 = R x0 + t */
	double t_cam1_cam0[3]; /**< metres */
	double rms_px;         /**< calibration reprojection RMS (0: unknown / synthetic) */
};

/** An 8-bit grey image (caller-owned pixels). */
struct rs_optical_image {
	const uint8_t *pixels;
	int width, height;
	size_t stride; /**< bytes per row, >= width */
};

/**
 * Check a rig: positive image sizes (<= 16384), finite positive focal lengths, principal
 * point inside the image, finite distortion, R a rotation (|R^T R - I| < 1e-6, det +1),
 * baseline > 1 mm. RS_ERR_BAD_DATA with a message naming the field.
 */
enum rs_status rs_optical_rig_check(const struct rs_optical_rig *rig, struct rs_error *err);

/**
 * The example rig of the tests, tools and docs: two width x height cameras without
 * distortion, f = 1.25 * width px (800 px at 640), principal point at the image centre,
 * camera 1 `baseline_m` to the right of camera 0 and toed in so the optical axes meet 1 m
 * in front of camera 0.
 */
void rs_optical_rig_example(double baseline_m, int width, int height, struct rs_optical_rig *out);

/**
 * Load a rig from an OpenCV FileStorage file (YAML or JSON by extension, see
 * docs/optical.md) and check it. RS_ERR_NOT_FOUND, RS_ERR_PARSE (malformed or a missing
 * key) or RS_ERR_BAD_DATA (rs_optical_rig_check()). *out written only on RS_OK.
 */
enum rs_status rs_optical_rig_load(const char *path, struct rs_optical_rig *out,
                                   struct rs_error *err);

/** Save a rig (".yaml"/".yml" or ".json"), through a temporary file renamed on success. */
enum rs_status rs_optical_rig_save(const char *path, const struct rs_optical_rig *rig,
                                   struct rs_error *err);

/** Checkerboard calibration target: inner corners and square size. */
struct rs_optical_board {
	int cols, rows;  /**< inner corners per row / column (default 9 x 6) */
	double square_m; /**< square side (default 0.025 m) */
};

/**
 * Calibrate both cameras (calibrateCamera) and the pair (stereoCalibrate, intrinsics
 * fixed) from n simultaneous checkerboard views. Views where the board is not found in
 * both images are skipped; fewer than 5 usable views: RS_ERR_DEGENERATE. out->rms_px is
 * the stereo reprojection RMS; out_used (may be NULL) the views used.
 */
enum rs_status rs_optical_calibrate(const struct rs_optical_board *board,
                                    const struct rs_optical_image *views0,
                                    const struct rs_optical_image *views1, size_t n,
                                    struct rs_optical_rig *out, size_t *out_used,
                                    struct rs_error *err);

/** Blob detector options; zero means default. */
struct rs_optical_detect_desc {
	int threshold;      /**< grey level a marker pixel exceeds (default 100) */
	double min_area_px; /**< smaller blobs are noise (default 3) */
	double max_area_px; /**< larger blobs are lamps, reflections or merged markers (400) */
	double max_aspect;  /**< longer / shorter axis (second moments) above this is a streak
	                         or two merged markers (default 1.6) */
};

/** A detected blob: intensity-weighted sub-pixel centroid (pixel centres at integers). */
struct rs_optical_blob {
	double x, y;
	double area_px;
	double aspect; /**< sqrt of the second-moment eigenvalue ratio */
};

/**
 * Bright blobs of `img` that pass the area and shape gates, at most `cap` (the brightest
 * first beyond that). *out_n blobs written. RS_ERR_INVALID for a malformed image.
 */
enum rs_status rs_optical_detect(const struct rs_optical_detect_desc *desc,
                                 const struct rs_optical_image *img, struct rs_optical_blob *out,
                                 size_t cap, size_t *out_n, struct rs_error *err);

/** Tracker options; zero means default. */
/** Most rectangles in one camera's mask. */
#define RS_OPTICAL_MAX_MASK_RECTS 16

/** A pixel rectangle: columns x .. x + width - 1, rows y .. y + height - 1. */
struct rs_optical_rect {
	int32_t x, y, width, height;
};

/**
 * Image regions of one camera to ignore (a lamp, a window, a glossy surface that the room
 * always shows): a blob whose centroid window (its pixels and the 3 px the centroid's
 * flanks need) touches one is not used, and counted in the quality's blobs_masked.
 * Rectangles, a mask image, or both.
 */
struct rs_optical_mask {
	struct rs_optical_rect rects[RS_OPTICAL_MAX_MASK_RECTS];
	uint32_t count; /**< rects used (0: none) */
	/** A grey mask image of the camera's size, `stride` bytes a row: a nonzero pixel is
	 *  masked. NULL: none. The tracker copies it at creation. */
	const uint8_t *pixels;
	int32_t width, height;
	size_t stride;
};

struct rs_optical_tracker_desc {
	struct rs_optical_rig rig;            /**< required (checked) */
	struct rs_pose_layout layout;         /**< all zero: rs_pose_layout_default() */
	struct rs_optical_detect_desc detect; /**< blob gates */
	double epipolar_gate_px;              /**< max distance from the epipolar line (default
	                                           max(2, 6 sqrt(2) centroid_sigma_px)) */
	double centroid_sigma_px;             /**< expected centroid noise (0.3), for quality */
	double side_tolerance_m;              /**< worst side-length mismatch of a triple (0.01;
	                                           with a layout verifier below
	                                           RS_POSE_LAYOUT_MIN_VERIFIER_M) */
	struct rs_optical_mask mask[2];       /**< per camera: regions to ignore (none) */
};

/** Why a frame pair gave no markers (or RS_OPTICAL_SOLVED when it did). */
enum rs_optical_verdict {
	RS_OPTICAL_SOLVED = 0,          /**< three markers in the sample */
	RS_OPTICAL_ONE_VIEW = 1,        /**< a frame from one camera only */
	RS_OPTICAL_TOO_FEW_MATCHES = 2, /**< fewer than three usable blob pairs (occluded,
	                                     merged, at the edge, crowded) */
	RS_OPTICAL_NO_LAYOUT = 3,       /**< no triple within side_tolerance_m of the layout */
	RS_OPTICAL_REPROJECTION = 4,    /**< a marker's reprojection error in the two views is
	                                     beyond its chi-square bound for centroid_sigma_px */
	RS_OPTICAL_MARKER_RESIDUAL = 5, /**< the two sides meeting at a marker are beyond their
	                                     chi-square bound (2 degrees of freedom) */
	RS_OPTICAL_SIDE_RESIDUAL = 6,   /**< the triangle's side lengths are beyond the total
	                                     chi-square bound (3 degrees of freedom) */
	RS_OPTICAL_AMBIGUOUS = 7,       /**< two triples fit the layout (a reflection of the
	                                     display) and the last frame's does not settle it */
	RS_OPTICAL_STEP = 8,            /**< the pose jumped from its prediction (the last
	                                     reported pose, constant velocity) beyond both
	                                     poses' stated errors and a hand's acceleration
	                                     (rs_pose_step_score()) */
	RS_OPTICAL_SPOT_SIZE = 9,       /**< a marker's spot differs in size between the views
	                                     beyond the other markers' (another light on its
	                                     epipolar line, docs/optical.md) */
	RS_OPTICAL_VERIFIER = 10,       /**< the layout's verifier light is seen, but not where
	                                     the pose puts it: beyond the chi-square bound of
	                                     the pose's and the centroids' errors (a stray spot
	                                     taken for a marker, docs/optical.md "The verifier") */
};

/** Constant name of a verdict ("RS_OPTICAL_REPROJECTION"); never NULL. */
const char *rs_optical_verdict_name(enum rs_optical_verdict verdict);

/** The chi-square bounds of the consistency gate (false alarm 2e-5 each, docs/optical.md). */
#define RS_OPTICAL_CHI2_1DOF 18.0
#define RS_OPTICAL_CHI2_2DOF 21.6
#define RS_OPTICAL_CHI2_3DOF 24.4
#define RS_OPTICAL_CHI2_4DOF 27.0

/** What one frame pair gave. */
struct rs_optical_quality {
	uint32_t blobs[2];       /**< blobs that passed the gates per view */
	uint32_t matches;        /**< blob pairs on each other's epipolar line */
	uint32_t markers;        /**< markers in the sample (3, or 0 when none could be found) */
	double reprojection_px;  /**< RMS reprojection error of the three markers */
	double side_error_m;     /**< worst side-length mismatch of the chosen triple */
	double sigma_m;          /**< predicted per-axis RMS 3-D error of a marker (from
	                              centroid_sigma_px through the triangulation): the
	                              noise_sigma_m to give rs_pose_solver */
	double rotation_rms_rad; /**< predicted RMS rotation error of the pose solved from these
	                              markers: each marker's triangulation covariance propagated
	                              through the rigid fit (docs/optical.md) */
	double position_rms_m;   /**< the same for the 3-D position of the display origin */
	enum rs_optical_verdict verdict; /**< why there are no markers (SOLVED when there are) */
	uint32_t blobs_at_edge[2]; /**< blobs not used: centroid window cut by the image edge */
	uint32_t blobs_crowded[2]; /**< blobs not used: another bright region in the window */
	double reprojection_chi2;  /**< worst marker's squared reprojection error over its
	                                variance (1 degree of freedom) */
	double marker_chi2;        /**< worst marker's chi-square of its two sides (2 degrees) */
	double side_chi2;          /**< side-length chi-square of the triple (3 degrees) */
	double step_score;         /**< rs_pose_step_score() from the prediction (0: none) */
	double bound_rotation_rad; /**< the integrity bound (a protection level): the largest
	                                rotation error this pose can have and still pass every
	                                test if one undetected stray spot replaced a marker's
	                                spot (the fault the side tests cannot see, cold: all of
	                                it; tracked: what the step gate also passes), plus 5x
	                                the stated error for the noise; raystream-track prints
	                                it as `bound=` (docs/optical.md, "The stated error and
	                                the integrity bound") */
	double bound_position_m;   /**< the same for the display origin's position */
	uint32_t blobs_masked[2];  /**< blobs not used: window touches the camera's mask */
	/** The error this pose claims, what raystream-track prints as `stated=`: its expected
	 * (RMS) error, the noise law with lens distortion (equal to rotation_rms_rad; on clean
	 * frames the measured RMS error is ~1.0x of it). What one undetected stray could add
	 * is not in it but in bound_rotation_rad (docs/optical.md, "The stated error and the
	 * integrity bound"). */
	double stated_rotation_rad;
	double stated_position_m; /**< the same for the display origin's position */
	/** Reported poses in a row before this one when it had a prior (the step gate's
	 *  prediction); 0: a cold pose, or the second of a row, whose velocity is not known
	 *  yet. */
	uint32_t prior_frames;
	/** With a layout verifier (rs_pose_layout.has_verifier): the views in which it was
	 *  found where this pose puts it, 0-2. 0 on a solved frame: it was hidden in both (not
	 *  within the integrity bound's reach of where the pose puts it), so the pose is only
	 *  as good as three markers make it (its integrity bound). 2: the pose is fitted to
	 *  the markers and the verifier, its stated errors the four points' law.
	 *  raystream-track prints `verifier=N`. Always 0 without a verifier. */
	uint32_t verifier_views;
	double verifier_chi2;  /**< its squared offset from where the pose puts it over the
	                            offset's covariance (2 degrees of freedom a view; 0: not seen) */
	uint32_t has_verifier; /**< 1: the tracker's layout has a verifier */
};

struct rs_optical_tracker;

/** Create a tracker; the caller frees it with rs_optical_tracker_destroy(). */
enum rs_status rs_optical_tracker_create(const struct rs_optical_tracker_desc *desc,
                                         struct rs_optical_tracker **out, struct rs_error *err);

/** Free a tracker; accepts NULL and sets *tracker to NULL. */
void rs_optical_tracker_destroy(struct rs_optical_tracker **tracker);

/**
 * Detect, match, triangulate and label the markers of one frame pair into `out`
 * (host_time_s = time_s, ids 0..2 by the layout's side lengths, camera-0 frame). When the
 * three markers cannot be found (occluded, merged, one view missing, ambiguous) the
 * sample has marker_count 0 and quality->markers 0: the pose solver then holds. Both
 * images must have the rig's sizes (RS_ERR_BAD_DATA otherwise); `img1` NULL (a frame from
 * one camera only) gives an empty sample. Buffers are reused across calls (OpenCV's
 * undistortPoints allocates small temporaries).
 * @param out_quality may be NULL
 */
enum rs_status rs_optical_tracker_process(struct rs_optical_tracker *tracker,
                                          const struct rs_optical_image *img0,
                                          const struct rs_optical_image *img1, double time_s,
                                          struct rs_marker_sample *out,
                                          struct rs_optical_quality *out_quality,
                                          struct rs_error *err);

/**
 * The same from blob centroids found elsewhere (cameras that centroid on board, as PPT
 * cameras do): `blobs0` / `blobs1` in distorted pixel coordinates of each camera (only x
 * and y are read). At most 24 blobs per view are used; a centroid within 4 px of the image
 * edge is not (its spot was clipped; counted in blobs_at_edge).
 */
enum rs_status rs_optical_tracker_process_blobs(struct rs_optical_tracker *tracker,
                                                const struct rs_optical_blob *blobs0, size_t n0,
                                                const struct rs_optical_blob *blobs1, size_t n1,
                                                double time_s, struct rs_marker_sample *out,
                                                struct rs_optical_quality *out_quality,
                                                struct rs_error *err);

/** Synthetic frames: what the rig sees of the markers, with the disturbances. */
struct rs_optical_synth_desc {
	double marker_radius_m; /**< LED radius (default 0.004 m) */
	double noise_grey;      /**< Gaussian pixel noise, grey levels RMS (0) */
	double blur_px;         /**< extra Gaussian blur sigma (0) */
	double background_grey; /**< background level (default 10) */
	double peak_grey;       /**< marker peak level (default 230) */
	int dim_marker;         /**< 1 + id of a marker drawn at half brightness (0: none; 4:
	                             the layout's verifier) */
	int occluded_marker;    /**< 1 + id of a marker hidden in camera 1 (0: none; 4: the
	                             layout's verifier) */
	int stray_light;        /**< nonzero: a round lamp-sized light in both views */
	int reflection;         /**< nonzero: an elongated specular streak in both views */
	uint64_t seed;          /**< noise seed */
};

/**
 * Render the markers of `layout` (and its verifier, if it has one) at T_cam0_markers into
 * two caller-owned images of the
 * rig's sizes (stride = width). Marker discs are integrated over each pixel, so their
 * intensity centroid is the projected centre to ~0.01 px.
 */
enum rs_status rs_optical_synth_render(const struct rs_optical_rig *rig,
                                       const struct rs_pose_layout *layout,
                                       const struct rs_pose *T_cam0_markers,
                                       const struct rs_optical_synth_desc *desc, uint8_t *out0,
                                       uint8_t *out1, struct rs_error *err);

/**
 * Render a checkerboard at T_cam0_board (board frame: corners on z = 0, x along cols)
 * into two images of the rig's sizes, for calibration tests. RS_ERR_DEGENERATE when the
 * board is not wholly in front of both cameras.
 */
enum rs_status rs_optical_synth_board(const struct rs_optical_rig *rig,
                                      const struct rs_optical_board *board,
                                      const struct rs_pose *T_cam0_board, uint8_t *out0,
                                      uint8_t *out1, struct rs_error *err);

/** Write an 8-bit grey PNG (temporary file renamed on success). */
enum rs_status rs_optical_write_png(const char *path, const uint8_t *pixels, int width, int height,
                                    struct rs_error *err);

/** A stream of grey frames: an image sequence, a video file or a V4L2 camera. */
struct rs_optical_frames;

/**
 * Open `what`: a printf pattern of an image sequence ("left_%04d.png", numbered from 0), a
 * video file, or with `camera` nonzero a V4L2 camera index ("0") or path ("/dev/video2").
 * RS_ERR_IO (RS_ERR_NOT_FOUND for a camera) when it cannot be opened.
 */
enum rs_status rs_optical_frames_open(const char *what, int camera, struct rs_optical_frames **out,
                                      struct rs_error *err);

/**
 * The next frame, converted to 8-bit grey, into *out (pixels owned by the stream, valid
 * until the next read or destroy). RS_END after the last frame of a file or sequence;
 * RS_ERR_IO when even the first frame cannot be read; RS_ERR_DISCONNECTED when a camera
 * stops.
 */
enum rs_status rs_optical_frames_read(struct rs_optical_frames *frames,
                                      struct rs_optical_image *out, struct rs_error *err);

/** Close; accepts NULL and sets *frames to NULL. */
void rs_optical_frames_destroy(struct rs_optical_frames **frames);

/**
 * Open a video: source: `LEFT,RIGHT?calib=FILE[&layout=FILE][&rate=HZ][&sigma_px=PX]` (PX:
 * the tracker's centroid_sigma_px) where LEFT and
 * RIGHT are printf patterns of image sequences ("left_%04d.png", numbered from 0) or
 * video files; or a cam: source: `0,1?calib=FILE` (V4L2 indices or /dev/video paths).
 * `rest` is the URI after the scheme. Frames become marker samples (rs_optical_tracker);
 * RS_END after the last frame of a sequence.
 */
enum rs_status rs_optical_open_uri(const char *scheme, const char *rest,
                                   struct rs_track_source **out, struct rs_error *err);

/**
 * The quality of the last frame pair a video: or cam: source (from rs_optical_open_uri or
 * rs_tracker_open) turned into a sample: its stated pose errors and, for a sample without
 * markers, the verdict saying why. False (nothing written) for any other source or before
 * its first sample.
 */
bool rs_optical_source_quality(const struct rs_track_source *src, struct rs_optical_quality *out);

#ifdef __cplusplus
}
#endif
#endif
