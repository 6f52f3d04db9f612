/* Camera, lights, environment and ambient: validation, defaults and read access. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "private/rs_vec.h"
#include "scene_internal.h"

static int finite_n(const double *v, int n)
{
	for (int i = 0; i < n; ++i)
		if (!isfinite(v[i]))
			return 0;
	return 1;
}

enum rs_status rs_camera_check(const struct rs_camera *camera, struct rs_error *err)
{
	RS_ASSERT(camera);
	if (!finite_n(camera->eye, 3) || !finite_n(camera->target, 3) || !finite_n(camera->up, 3) ||
	    !isfinite(camera->fov_y_deg) || !finite_n(camera->shift, 2))
		return rs_error_set(err, RS_ERR_BAD_DATA, "camera has a non-finite value");
	double view[3] = {camera->target[0] - camera->eye[0], camera->target[1] - camera->eye[1],
	                  camera->target[2] - camera->eye[2]};
	double side[3];
	rs_v3_cross(view, camera->up, side);
	/* Finite ends can still be infinitely far apart (eye 1e308, target -1e308); then the
	 * checks below compare NaN and would pass. */
	if (!finite_n(view, 3) || !isfinite(rs_v3_dot(view, view)) ||
	    !isfinite(rs_v3_dot(camera->up, camera->up)))
		return rs_error_set(err, RS_ERR_BAD_DATA, "camera eye, target or up is too large");
	if (rs_v3_dot(view, view) == 0.0)
		return rs_error_set(err, RS_ERR_BAD_DATA, "camera eye equals its target");
	if (rs_v3_dot(side, side) <=
	        1e-12 * rs_v3_dot(view, view) * rs_v3_dot(camera->up, camera->up) ||
	    rs_v3_dot(camera->up, camera->up) == 0.0)
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "camera up is zero or parallel to the view direction");
	if (camera->fov_y_deg < 0.0 || camera->fov_y_deg >= 180.0)
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "camera field of view %g is outside (0, 180)",
		                    camera->fov_y_deg);
	if (fabs(camera->shift[0]) > 1e6 || fabs(camera->shift[1]) > 1e6)
		return rs_error_set(err, RS_ERR_BAD_DATA, "camera lens shift (%g, %g) is too large",
		                    camera->shift[0], camera->shift[1]);
	if (camera->width > 16384 || camera->height > 16384)
		return rs_error_set(err, RS_ERR_LIMIT, "camera image %ux%u is too large",
		                    camera->width, camera->height);
	return RS_OK;
}

enum rs_status rs_scene_set_camera(struct rs_scene *scene, const struct rs_camera *camera,
                                   struct rs_error *err)
{
	RS_ASSERT(scene && camera);
	enum rs_status status = rs_camera_check(camera, err);
	if (status == RS_OK)
		scene->camera = *camera;
	return status;
}

enum rs_status rs_scene_add_light(struct rs_scene *scene, const struct rs_light *light,
                                  struct rs_error *err)
{
	RS_ASSERT(scene && light);
	if (!finite_n(light->position, 3) || !finite_n(light->color, 3))
		return rs_error_set(err, RS_ERR_BAD_DATA, "light has a non-finite value");
	if (light->color[0] < 0 || light->color[1] < 0 || light->color[2] < 0)
		return rs_error_set(err, RS_ERR_BAD_DATA, "light colour is negative");
	if (scene->light_count == scene->light_capacity) {
		size_t cap = scene->light_capacity ? scene->light_capacity * 2 : 4;
		struct rs_light *p = realloc(scene->lights, cap * sizeof *p);
		if (!p)
			return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory adding a light");
		scene->lights = p;
		scene->light_capacity = cap;
	}
	scene->lights[scene->light_count++] = *light;
	return RS_OK;
}

enum rs_status rs_scene_set_environment(struct rs_scene *scene,
                                        const struct rs_environment *environment,
                                        struct rs_error *err)
{
	RS_ASSERT(scene && environment);
	const struct rs_environment *e = environment;
	if (!finite_n(e->center, 3) || !isfinite(e->half_size) || e->half_size < 0.0 ||
	    !isfinite(e->line_width) || !isfinite(e->line_scale) || e->line_width < 0.0f ||
	    e->line_width > 1.0f || e->line_scale < 0.0f)
		return rs_error_set(err, RS_ERR_BAD_DATA,
		                    "environment has a non-finite or out-of-range value");
	for (int f = 0; f < 6; ++f)
		for (int c = 0; c < 3; ++c)
			if (!isfinite(e->face_color[f][c]) || e->face_color[f][c] < 0.0f)
				return rs_error_set(err, RS_ERR_BAD_DATA,
				                    "environment face %d colour is invalid", f);
	if (e->grid > 4096)
		return rs_error_set(err, RS_ERR_BAD_DATA, "environment grid %u is too fine",
		                    e->grid);
	scene->environment = *e;
	return RS_OK;
}

enum rs_status rs_scene_set_ambient(struct rs_scene *scene, double ambient, struct rs_error *err)
{
	RS_ASSERT(scene);
	if (!isfinite(ambient) || ambient < 0.0)
		return rs_error_set(err, RS_ERR_BAD_DATA, "ambient %g is invalid", ambient);
	scene->ambient = ambient;
	return RS_OK;
}

size_t rs_scene_triangle_count(const struct rs_scene *s)
{
	return s->triangle_count;
}
size_t rs_scene_vertex_count(const struct rs_scene *s)
{
	return s->vertex_count;
}
const float *rs_scene_positions(const struct rs_scene *s)
{
	return s->positions;
}

const double *rs_scene_positions_f64(const struct rs_scene *s)
{
	return s->positions_f64;
}
const float *rs_scene_normals(const struct rs_scene *s)
{
	return s->normals;
}
const uint32_t *rs_scene_indices(const struct rs_scene *s)
{
	return s->indices;
}
const uint32_t *rs_scene_triangle_materials(const struct rs_scene *s)
{
	return s->triangle_materials;
}
size_t rs_scene_material_count(const struct rs_scene *s)
{
	return s->material_count;
}
const struct rs_material *rs_scene_materials(const struct rs_scene *s)
{
	return s->materials;
}
size_t rs_scene_light_count(const struct rs_scene *s)
{
	return s->light_count;
}
const struct rs_light *rs_scene_lights(const struct rs_scene *s)
{
	return s->lights;
}
const struct rs_camera *rs_scene_camera(const struct rs_scene *s)
{
	return &s->camera;
}
double rs_scene_ambient(const struct rs_scene *s)
{
	return s->ambient;
}

void rs_scene_bounds(const struct rs_scene *scene, struct rs_bounds *out)
{
	if (scene->triangle_count == 0) {
		for (int a = 0; a < 3; ++a) {
			out->lo[a] = INFINITY;
			out->hi[a] = -INFINITY;
		}
		return;
	}
	*out = scene->bounds;
	if (!scene->bounds_stale)
		return;
	/* instances moved: the union of the parts, the same min and max as over every vertex */
	*out = scene->mesh_bounds;
	for (size_t i = 0; i < scene->instance_count; ++i) {
		rs__scene_bounds_add(out, scene->instance_bounds[i].lo);
		rs__scene_bounds_add(out, scene->instance_bounds[i].hi);
	}
}

void rs_scene_environment(const struct rs_scene *scene, struct rs_environment *out)
{
	*out = scene->environment;
	if (out->half_size == 0.0) {
		struct rs_bounds b;
		rs_scene_bounds(scene, &b);
		double extent = 0.0;
		for (int a = 0; a < 3 && scene->triangle_count; ++a) {
			out->center[a] = 0.5 * (b.lo[a] + b.hi[a]);
			extent = fmax(extent, b.hi[a] - b.lo[a]);
		}
		out->half_size = extent > 0.0 ? 2.0 * extent : 1.0;
	}
	if (out->grid == 0)
		out->grid = 16;
	if (out->line_width == 0.0f)
		out->line_width = 0.06f;
	if (out->line_scale == 0.0f)
		out->line_scale = 0.25f;
}

void rs_camera_resolve(const struct rs_camera *in, struct rs_camera *out)
{
	*out = *in;
	if (out->fov_y_deg == 0.0)
		out->fov_y_deg = 45.0;
	if (out->width == 0)
		out->width = 512;
	if (out->height == 0)
		out->height = 512;
}

void rs_camera_frame(const struct rs_bounds *focus, double elevation_deg, struct rs_camera *camera)
{
	struct rs_camera resolved;
	rs_camera_resolve(camera, &resolved);
	double half_fov = resolved.fov_y_deg * 0.5 * RS_PI / 180.0;
	double d2 = 0.0, center[3];
	for (int a = 0; a < 3; ++a) {
		/* An empty or non-finite box (an empty scene's bounds) frames the origin rather
		 * than writing NaN into the camera. */
		int ok = isfinite(focus->lo[a]) && isfinite(focus->hi[a]) &&
		         focus->lo[a] <= focus->hi[a];
		center[a] = ok ? 0.5 * (focus->lo[a] + focus->hi[a]) : 0.0;
		double e = ok ? focus->hi[a] - focus->lo[a] : 0.0;
		d2 += e * e;
	}
	if (!isfinite(d2))
		d2 = 0.0;
	double r = 0.5 * sqrt(d2);
	double dist = r > 0.0 ? r / sin(half_fov) : 1.0;
	double el = elevation_deg * RS_PI / 180.0;
	camera->eye[0] = center[0];
	camera->eye[1] = center[1] + dist * sin(el);
	camera->eye[2] = center[2] + dist * cos(el);
	memcpy(camera->target, center, sizeof center);
	camera->up[0] = 0.0;
	camera->up[1] = 1.0;
	camera->up[2] = 0.0;
}
