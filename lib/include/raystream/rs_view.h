/**
 * @file rs_view.h
 * From the tracked display's pose to the render camera (module rs_view): the display's
 * calibration (where the screen rectangle sits relative to the tracked markers, where the
 * eye is, how the tracker room maps into the scene) and two ways of looking:
 *
 * - RS_VIEW_HEAD_COUPLED: the handheld is a window into the scene. The camera sits at the
 *   eye, looks perpendicular to the screen, and its off-axis frustum (fov + lens shift)
 *   passes exactly through the screen rectangle's four corners.
 * - RS_VIEW_CAMERA: a camera on the handheld: at the screen centre, looking along the
 *   screen's inward normal (the paper's "normal of the plane the sensors span"), fixed fov.
 *
 * Frames (T_A_B maps B-frame points into A, as rs_pose.h): the pose solver gives
 * T_tracker_display; the calibration adds T_display_screen (screen frame: origin at the
 * screen centre, x right, y up, z out of the screen towards the viewer) and T_scene_tracker
 * (with a scale: scene units per metre). See docs/view.md.
 */
#ifndef RS_VIEW_H
#define RS_VIEW_H

#include <stdint.h>

#include "raystream/rs_pose.h"
#include "raystream/rs_scene.h"
#include "raystream/rs_status.h"
#include "raystream/rs_track_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How the camera follows the display. */
enum rs_view_mode {
	RS_VIEW_HEAD_COUPLED = 0, /**< eye + screen rectangle: off-axis window (default) */
	RS_VIEW_CAMERA = 1,       /**< a camera fixed on the handheld, centred frustum */
};

/** Which frame rs_view_calibration.eye is given in. */
enum rs_view_eye_frame {
	RS_VIEW_EYE_IN_SCREEN = 0,  /**< the eye moves with the handheld (default) */
	RS_VIEW_EYE_IN_TRACKER = 1, /**< the eye stays at a point of the tracker room */
};

/** Default screen rectangle side: the square image on the paper's UMPC (58 mm tall). */
#define RS_VIEW_DEFAULT_SCREEN_M 0.058
/** Default eye distance in front of the screen centre. */
#define RS_VIEW_DEFAULT_EYE_M 0.35
/** Default closest eye-to-screen-plane distance: nearer is "edge-on" and refused. */
#define RS_VIEW_DEFAULT_MIN_EYE_DISTANCE_M 0.005
/** Default widest vertical fov a head-coupled frustum may need before it is refused. */
#define RS_VIEW_DEFAULT_MAX_FOV_DEG 160.0
/** Largest relative difference between the image's and the screen's aspect ratios. */
#define RS_VIEW_ASPECT_TOLERANCE 0.01

/** The display calibration; zero-initialised means defaults (rs_view_calibration_resolve). */
struct rs_view_calibration {
	enum rs_view_mode mode;
	/** Screen frame in the display frame; an all-zero orientation means identity. */
	struct rs_pose T_display_screen;
	/** The rectangle the image fills, metres; 0 -> RS_VIEW_DEFAULT_SCREEN_M each. */
	double screen_width_m, screen_height_m;
	enum rs_view_eye_frame eye_frame;
	/** The eye, metres, in the frame eye_frame names. All zero with RS_VIEW_EYE_IN_SCREEN
	 * means (0, 0, RS_VIEW_DEFAULT_EYE_M) (an eye on the screen itself is never valid). */
	double eye[3];
	/** The tracker room in the scene; an all-zero orientation means identity. */
	struct rs_pose T_scene_tracker;
	double scene_units_per_m;  /**< 0 -> 1 */
	double fov_y_deg;          /**< RS_VIEW_CAMERA's vertical fov; 0 -> 45 */
	double min_eye_distance_m; /**< 0 -> RS_VIEW_DEFAULT_MIN_EYE_DISTANCE_M */
	double max_fov_deg;        /**< 0 -> RS_VIEW_DEFAULT_MAX_FOV_DEG (< 180) */
};

/**
 * Copy `cal` (NULL: all defaults) into `out` with defaults filled in, quaternions
 * normalised. RS_ERR_INVALID for unknown enums, negative or non-finite sizes/distances,
 * a zero or non-finite quaternion that is not all zero, fovs outside (0, 180).
 */
enum rs_status rs_view_calibration_resolve(const struct rs_view_calibration *cal,
                                           struct rs_view_calibration *out, struct rs_error *err);

/** Where the eye and the screen are in the scene (what a camera was made from). */
struct rs_view_geometry {
	double eye[3];                     /**< scene units */
	double screen_center[3];           /**< scene units */
	double right[3], up[3], normal[3]; /**< screen axes in the scene, unit; normal: out */
	double eye_distance_m; /**< eye to screen plane along the normal (> 0: in front) */
};

/**
 * The camera for one pose, stateless. `width` x `height` is the image size (only its
 * aspect ratio is used; in RS_VIEW_HEAD_COUPLED it must match the screen rectangle's
 * within RS_VIEW_ASPECT_TOLERANCE, or pixels would not be square: RS_ERR_INVALID).
 * @param cal            a resolved calibration (rs_view_calibration_resolve())
 * @param out_geometry   may be NULL
 * @return RS_OK; RS_ERR_BAD_DATA (non-finite pose or zero quaternion);
 *         RS_ERR_DEGENERATE (head-coupled: eye behind the screen, edge-on: nearer its plane
 *         than min_eye_distance_m, or a frustum wider than max_fov_deg); RS_ERR_INVALID.
 *         *out_camera is written only on RS_OK.
 */
enum rs_status rs_view_camera_from_pose(const struct rs_view_calibration *cal,
                                        const struct rs_pose *T_tracker_display, uint32_t width,
                                        uint32_t height, struct rs_camera *out_camera,
                                        struct rs_view_geometry *out_geometry,
                                        struct rs_error *err);

/**
 * Re-seat the tracker room in the scene so that `T_tracker_display` gives the camera
 * `home` (its eye, forward direction and up; fov and shift still come from the
 * calibration): the viewer's "recentre" key. Only cal->T_scene_tracker changes.
 * @return RS_OK; RS_ERR_BAD_DATA (non-finite pose); RS_ERR_DEGENERATE (home's forward
 *         and up are parallel or zero).
 */
enum rs_status rs_view_recentre(struct rs_view_calibration *cal,
                                const struct rs_pose *T_tracker_display,
                                const struct rs_camera *home, struct rs_error *err);

/** How far a camera from rs_view_update() can be trusted. */
enum rs_view_state {
	RS_VIEW_FRESH = 0,     /**< from a pose the solver solved from this sample */
	RS_VIEW_PREDICTED = 1, /**< from a pose the solver held or extrapolated */
	RS_VIEW_STALE = 2,     /**< pose lost or camera refused: the last good camera again */
	RS_VIEW_HOME = 3,      /**< no good camera yet: the home camera */
};

/** Constant name of a view state ("RS_VIEW_STALE"); never NULL. */
const char *rs_view_state_name(enum rs_view_state state);

/** A camera tracker over time: keeps the last good camera for when the pose is lost. */
struct rs_view;

/**
 * Create a view. `cal` NULL: defaults (copied and resolved); `home` is the camera given
 * before any pose was good (usually the scene's). Destroy with rs_view_destroy().
 */
enum rs_status rs_view_create(const struct rs_view_calibration *cal, const struct rs_camera *home,
                              uint32_t width, uint32_t height, struct rs_view **out,
                              struct rs_error *err);

/** Free a view; accepts NULL and sets *view to NULL. */
void rs_view_destroy(struct rs_view **view);

/**
 * The camera for a solved pose and its status (from rs_pose_solver_update()). RS_POSE_NONE
 * and poses rs_view_camera_from_pose() refuses give the last good camera flagged
 * RS_VIEW_STALE (or the home camera, RS_VIEW_HOME); the reason is in
 * rs_view_last_error(). Always writes *out_camera and *out_state; cannot fail (NULL
 * arguments are contract violations).
 */
void rs_view_update(struct rs_view *view, const struct rs_pose *T_tracker_display,
                    enum rs_pose_status pose_status, struct rs_camera *out_camera,
                    enum rs_view_state *out_state);

/** Recentre on the last pose given to rs_view_update() (rs_view_recentre() with the home
 * camera). RS_END when no pose was given yet. */
enum rs_status rs_view_recentre_last(struct rs_view *view, struct rs_error *err);

/** The calibration in use (resolved; changed by recentring); owned by the view. */
const struct rs_view_calibration *rs_view_calibration(const struct rs_view *view);

/** Why the last update was not fresh (or ""); owned by the view. */
const char *rs_view_last_error(const struct rs_view *view);

#ifdef __cplusplus
}
#endif
#endif
