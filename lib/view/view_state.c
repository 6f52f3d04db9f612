/* rs_view: the camera over time, keeping the last good one for a lost or refused pose. */
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_view.h"

struct rs_view {
	struct rs_view_calibration cal;
	struct rs_camera home, last_good;
	uint32_t width, height;
	int has_good, has_pose;
	struct rs_pose last_pose;
	struct rs_error err;
};

const char *rs_view_state_name(enum rs_view_state state)
{
	switch (state) {
	case RS_VIEW_FRESH:
		return "RS_VIEW_FRESH";
	case RS_VIEW_PREDICTED:
		return "RS_VIEW_PREDICTED";
	case RS_VIEW_STALE:
		return "RS_VIEW_STALE";
	case RS_VIEW_HOME:
		return "RS_VIEW_HOME";
	}
	return "RS_VIEW_UNKNOWN";
}

enum rs_status rs_view_create(const struct rs_view_calibration *cal, const struct rs_camera *home,
                              uint32_t width, uint32_t height, struct rs_view **out,
                              struct rs_error *err)
{
	RS_ASSERT(home && out);
	*out = NULL;
	if (width == 0 || height == 0)
		return rs_error_set(err, RS_ERR_INVALID, "view: image size %ux%u", width, height);
	struct rs_view_calibration resolved;
	enum rs_status st = rs_view_calibration_resolve(cal, &resolved, err);
	if (st != RS_OK)
		return st;
	struct rs_view *v = calloc(1, sizeof *v);
	if (!v)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "view: out of memory");
	v->cal = resolved;
	v->home = *home;
	v->width = width;
	v->height = height;
	*out = v;
	return RS_OK;
}

void rs_view_destroy(struct rs_view **view)
{
	if (!view)
		return;
	free(*view);
	*view = NULL;
}

void rs_view_update(struct rs_view *view, const struct rs_pose *T_tracker_display,
                    enum rs_pose_status pose_status, struct rs_camera *out_camera,
                    enum rs_view_state *out_state)
{
	RS_ASSERT(view && T_tracker_display && out_camera && out_state);
	rs_error_clear(&view->err);
	enum rs_status st = RS_ERR_BAD_DATA;
	struct rs_camera cam;
	if (pose_status == RS_POSE_NONE) {
		rs_error_set(&view->err, RS_ERR_BAD_DATA, "view: pose lost (RS_POSE_NONE)");
	} else {
		st = rs_view_camera_from_pose(&view->cal, T_tracker_display, view->width,
		                              view->height, &cam, NULL, &view->err);
		if (st == RS_OK || st == RS_ERR_DEGENERATE) {
			/* a refused camera still comes from a real pose: recentring on it is fine
			 */
			view->last_pose = *T_tracker_display;
			view->has_pose = 1;
		}
	}
	if (st == RS_OK) {
		view->last_good = cam;
		view->has_good = 1;
		*out_camera = cam;
		*out_state = pose_status == RS_POSE_OK || pose_status == RS_POSE_RELABELED
		                 ? RS_VIEW_FRESH
		                 : RS_VIEW_PREDICTED;
		return;
	}
	*out_camera = view->has_good ? view->last_good : view->home;
	*out_state = view->has_good ? RS_VIEW_STALE : RS_VIEW_HOME;
}

enum rs_status rs_view_recentre_last(struct rs_view *view, struct rs_error *err)
{
	RS_ASSERT(view);
	if (!view->has_pose)
		return rs_error_set(err, RS_END, "view: no pose to recentre on yet");
	return rs_view_recentre(&view->cal, &view->last_pose, &view->home, err);
}

const struct rs_view_calibration *rs_view_calibration(const struct rs_view *view)
{
	RS_ASSERT(view);
	return &view->cal;
}

const char *rs_view_last_error(const struct rs_view *view)
{
	RS_ASSERT(view);
	return view->err.message;
}
