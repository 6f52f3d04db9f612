/*
 * rs_load_scene: a mesh file plus its sidecar view file, or, without one, a camera and a
 * light framed the way the benchmark scenes frame theirs (SCENES.md), so any model renders
 * sensibly out of the box.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "raystream/rs_load.h"

/* SCENES.md's L1, relative to the herd centre. */
static const double k_l1_offset[3] = {-10.0, 25.0, 20.0};

static enum rs_status default_view(struct rs_scene *scene, struct rs_error *err)
{
	struct rs_bounds b;
	struct rs_camera cam;
	struct rs_light light;
	double diag = 0.0, len = 0.0, scale;
	enum rs_status st;

	rs_scene_bounds(scene, &b);
	memset(&cam, 0, sizeof(cam));
	cam.fov_y_deg = 45.0;
	cam.width = cam.height = 512;
	rs_camera_frame(&b, 30.0, &cam);
	st = rs_scene_set_camera(scene, &cam, err);
	if (st != RS_OK)
		return rs_error_prefix(err, st, "camera");
	for (int k = 0; k < 3; k++) {
		diag += (b.hi[k] - b.lo[k]) * (b.hi[k] - b.lo[k]);
		len += k_l1_offset[k] * k_l1_offset[k];
	}
	diag = sqrt(diag);
	len = sqrt(len);
	/* L1's offset as given for cow-sized models; pushed out for large ones so the light
	 * never ends up inside the model. */
	scale = diag > len ? diag / len : 1.0;
	memset(&light, 0, sizeof(light));
	for (int k = 0; k < 3; k++) {
		light.position[k] = 0.5 * (b.lo[k] + b.hi[k]) + scale * k_l1_offset[k];
		light.color[k] = 1.0;
	}
	st = rs_scene_add_light(scene, &light, err);
	if (st != RS_OK)
		return rs_error_prefix(err, st, "light");
	return RS_OK;
}

enum rs_status rs_load_scene(const struct rs_load_desc *desc, const char *path,
                             struct rs_scene **out, struct rs_error *err)
{
	struct rs_scene *scene = NULL;
	struct stat sb;
	char *sidecar;
	size_t len;
	enum rs_status st;

	RS_ASSERT(out && path);
	*out = NULL;
	len = strlen(path) + sizeof(".json");
	sidecar = malloc(len);
	if (sidecar == NULL)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory");
	rs_load_sidecar_path(path, sidecar, len, NULL);
	st = rs_scene_create(NULL, &scene, err);
	if (st == RS_OK)
		st = rs_load_mesh_file(desc, path, scene, err);
	if (st == RS_OK) {
		/* A sidecar that exists but is unreadable or bad is an error, not a default. */
		if (stat(sidecar, &sb) == 0 || errno != ENOENT)
			st = rs_load_view_file(sidecar, scene, err);
		else
			st = default_view(scene, err);
	}
	free(sidecar);
	if (st != RS_OK) {
		rs_scene_destroy(&scene);
		return st;
	}
	*out = scene;
	return RS_OK;
}
