/*
 * The view file: camera, lights, environment and ambient as JSON (cJSON), the companion
 * of an exported OBJ. Reading parses and checks the whole file into locals before the scene
 * is changed; writing relies on cJSON printing doubles with up to 17 digits, so values
 * read back bit-exactly.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load_internal.h"
#include "raystream/rs_load.h"

#define VIEW_FORMAT "raystream-view"
#define VIEW_VERSION 1
#define VIEW_MAX_BYTES ((size_t)16 << 20)
#define VIEW_MAX_LIGHTS 4096

struct view {
	int has_camera, has_env, has_ambient;
	struct rs_camera camera;
	struct rs_environment env;
	double ambient;
	struct rs_light *lights;
	size_t light_count;
};

/* Reads a number member; absent: keep *out, return RS_OK. `what` names it in errors. */
static enum rs_status get_number(const cJSON *obj, const char *key, const char *what, int required,
                                 double *out, struct rs_error *err)
{
	const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);

	if (item == NULL)
		return required ? rs_error_set(err, RS_ERR_PARSE, "%s.%s missing", what, key)
		                : RS_OK;
	if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble))
		return rs_error_set(err, RS_ERR_PARSE, "%s.%s: not a finite number", what, key);
	*out = item->valuedouble;
	return RS_OK;
}

static enum rs_status get_vec3(const cJSON *obj, const char *key, const char *what, int required,
                               double out[3], struct rs_error *err)
{
	const cJSON *item = key != NULL ? cJSON_GetObjectItemCaseSensitive(obj, key) : obj;
	const cJSON *e;
	double v[3];
	int n = 0;

	if (item == NULL)
		return required ? rs_error_set(err, RS_ERR_PARSE, "%s.%s missing", what, key)
		                : RS_OK;
	if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
		goto bad;
	cJSON_ArrayForEach(e, item)
	{
		if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
			goto bad;
		v[n++] = e->valuedouble;
	}
	memcpy(out, v, sizeof(v));
	return RS_OK;
bad:
	return rs_error_set(err, RS_ERR_PARSE, "%s%s%s: expected an array of 3 finite numbers",
	                    what, key != NULL ? "." : "", key != NULL ? key : "");
}

static enum rs_status get_uint(const cJSON *obj, const char *key, const char *what, double max,
                               uint32_t *out, struct rs_error *err)
{
	double v = 0.0;
	enum rs_status st = get_number(obj, key, what, 0, &v, err);

	if (st != RS_OK || cJSON_GetObjectItemCaseSensitive(obj, key) == NULL)
		return st;
	if (v < 0.0 || v > max || v != floor(v))
		return rs_error_set(err, RS_ERR_PARSE, "%s.%s: expected an integer 0..%.0f", what,
		                    key, max);
	*out = (uint32_t)v;
	return RS_OK;
}

static enum rs_status parse_camera(const cJSON *c, struct rs_camera *cam, struct rs_error *err)
{
	enum rs_status st;

	if (!cJSON_IsObject(c))
		return rs_error_set(err, RS_ERR_PARSE, "camera: expected an object");
	memset(cam, 0, sizeof(*cam));
	cam->up[1] = 1.0;
	if ((st = get_vec3(c, "eye", "camera", 1, cam->eye, err)) != RS_OK ||
	    (st = get_vec3(c, "target", "camera", 1, cam->target, err)) != RS_OK ||
	    (st = get_vec3(c, "up", "camera", 0, cam->up, err)) != RS_OK ||
	    (st = get_number(c, "fov_y_deg", "camera", 0, &cam->fov_y_deg, err)) != RS_OK ||
	    (st = get_uint(c, "width", "camera", 65536, &cam->width, err)) != RS_OK ||
	    (st = get_uint(c, "height", "camera", 65536, &cam->height, err)) != RS_OK)
		return st;
	return RS_OK;
}

static enum rs_status parse_lights(const cJSON *arr, struct view *v, struct rs_error *err)
{
	const cJSON *l;
	int n = cJSON_GetArraySize(arr);

	if (!cJSON_IsArray(arr))
		return rs_error_set(err, RS_ERR_PARSE, "lights: expected an array");
	if (n > VIEW_MAX_LIGHTS)
		return rs_error_set(err, RS_ERR_LIMIT, "lights: %d lights (limit %d)", n,
		                    VIEW_MAX_LIGHTS);
	v->lights = calloc((size_t)n + 1, sizeof(*v->lights));
	if (v->lights == NULL)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "lights: out of memory");
	cJSON_ArrayForEach(l, arr)
	{
		struct rs_light *light = &v->lights[v->light_count];
		enum rs_status st;

		if (!cJSON_IsObject(l))
			return rs_error_set(err, RS_ERR_PARSE, "lights[%zu]: expected an object",
			                    v->light_count);
		light->color[0] = light->color[1] = light->color[2] = 1.0;
		if ((st = get_vec3(l, "position", "lights[]", 1, light->position, err)) != RS_OK ||
		    (st = get_vec3(l, "color", "lights[]", 0, light->color, err)) != RS_OK)
			return st;
		v->light_count++;
	}
	return RS_OK;
}

static enum rs_status parse_environment(const cJSON *e, struct rs_environment *env,
                                        struct rs_error *err)
{
	const cJSON *faces = cJSON_GetObjectItemCaseSensitive(e, "face_colors");
	double num;
	enum rs_status st;

	if (!cJSON_IsObject(e))
		return rs_error_set(err, RS_ERR_PARSE, "environment: expected an object");
	if ((st = get_vec3(e, "center", "environment", 0, env->center, err)) != RS_OK ||
	    (st = get_number(e, "half_size", "environment", 0, &env->half_size, err)) != RS_OK ||
	    (st = get_uint(e, "grid", "environment", 4096, &env->grid, err)) != RS_OK)
		return st;
	num = env->line_width;
	if ((st = get_number(e, "line_width", "environment", 0, &num, err)) != RS_OK)
		return st;
	env->line_width = (float)num;
	num = env->line_scale;
	if ((st = get_number(e, "line_scale", "environment", 0, &num, err)) != RS_OK)
		return st;
	env->line_scale = (float)num;
	if (faces != NULL) {
		const cJSON *f;
		int i = 0;

		if (!cJSON_IsArray(faces) || cJSON_GetArraySize(faces) != 6)
			return rs_error_set(err, RS_ERR_PARSE,
			                    "environment.face_colors: expected 6 colours");
		cJSON_ArrayForEach(f, faces)
		{
			double c[3];

			if ((st = get_vec3(f, NULL, "environment.face_colors[]", 1, c, err)) !=
			    RS_OK)
				return st;
			for (int k = 0; k < 3; k++)
				env->face_color[i][k] = (float)c[k];
			i++;
		}
	}
	return RS_OK;
}

static enum rs_status parse_view(const cJSON *root, const struct rs_scene *scene, struct view *v,
                                 struct rs_error *err)
{
	const cJSON *item;
	enum rs_status st;

	if (!cJSON_IsObject(root))
		return rs_error_set(err, RS_ERR_PARSE, "expected a JSON object");
	item = cJSON_GetObjectItemCaseSensitive(root, "format");
	if (item != NULL && (!cJSON_IsString(item) || strcmp(item->valuestring, VIEW_FORMAT) != 0))
		return rs_error_set(err, RS_ERR_PARSE, "format: expected \"" VIEW_FORMAT "\"");
	item = cJSON_GetObjectItemCaseSensitive(root, "version");
	if (item != NULL && (!cJSON_IsNumber(item) || item->valuedouble != VIEW_VERSION))
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "version: only %d is supported",
		                    VIEW_VERSION);
	if ((item = cJSON_GetObjectItemCaseSensitive(root, "camera")) != NULL) {
		if ((st = parse_camera(item, &v->camera, err)) != RS_OK)
			return st;
		v->has_camera = 1;
	}
	if ((item = cJSON_GetObjectItemCaseSensitive(root, "lights")) != NULL &&
	    (st = parse_lights(item, v, err)) != RS_OK)
		return st;
	if ((item = cJSON_GetObjectItemCaseSensitive(root, "environment")) != NULL) {
		/* Unnamed fields keep the scene's values; no centre/size means "from bounds". */
		rs_scene_environment(scene, &v->env);
		memset(v->env.center, 0, sizeof(v->env.center));
		v->env.half_size = 0.0;
		if ((st = parse_environment(item, &v->env, err)) != RS_OK)
			return st;
		v->has_env = 1;
	}
	if ((st = get_number(root, "ambient", "view", 0, &v->ambient, err)) != RS_OK)
		return st;
	v->has_ambient = cJSON_GetObjectItemCaseSensitive(root, "ambient") != NULL;
	return RS_OK;
}

static enum rs_status apply_view(const struct view *v, struct rs_scene *scene, struct rs_error *err)
{
	enum rs_status st = RS_OK;
	const char *what = "";

	if (v->has_camera && (st = rs_scene_set_camera(scene, &v->camera, err)) != RS_OK)
		what = "camera";
	for (size_t i = 0; st == RS_OK && i < v->light_count; i++)
		if ((st = rs_scene_add_light(scene, &v->lights[i], err)) != RS_OK)
			what = "lights";
	if (st == RS_OK && v->has_env &&
	    (st = rs_scene_set_environment(scene, &v->env, err)) != RS_OK)
		what = "environment";
	if (st == RS_OK && v->has_ambient &&
	    (st = rs_scene_set_ambient(scene, v->ambient, err)) != RS_OK)
		what = "ambient";
	if (st != RS_OK)
		return rs_error_prefix(err, st, "%s", what);
	return RS_OK;
}

enum rs_status rs_load_view_file(const char *path, struct rs_scene *scene, struct rs_error *err)
{
	struct view v;
	char *text = NULL;
	size_t size = 0;
	cJSON *root;
	enum rs_status st;
	struct rs_error inner;

	RS_ASSERT(path && scene);
	st = rs_load_read_text(path, VIEW_MAX_BYTES, &text, &size, err);
	if (st != RS_OK)
		return st;
	root = cJSON_ParseWithLength(text, size);
	if (root == NULL) {
		const char *at = cJSON_GetErrorPtr();
		size_t offset =
		    at != NULL && at >= text && at <= text + size ? (size_t)(at - text) : 0;

		free(text);
		return rs_error_set(err, RS_ERR_PARSE, "%s: malformed JSON near byte %zu", path,
		                    offset);
	}
	free(text);
	memset(&v, 0, sizeof(v));
	rs_error_clear(&inner);
	st = parse_view(root, scene, &v, &inner);
	cJSON_Delete(root);
	if (st == RS_OK) {
		/* Dry run on an empty scene: whatever rs_scene rejects is found before the real
		 * scene changes (its checks do not depend on geometry). */
		struct rs_scene *scratch = NULL;

		st = rs_scene_create(NULL, &scratch, &inner);
		if (st == RS_OK)
			st = apply_view(&v, scratch, &inner);
		rs_scene_destroy(&scratch);
	}
	if (st == RS_OK)
		st = apply_view(&v, scene, &inner);
	free(v.lights);
	if (st != RS_OK)
		return rs_error_set(err, st, "%s: %s", path, inner.message);
	return RS_OK;
}

/*
 * A number that reads back bit-exactly. cJSON's own printer settles for 15 digits when
 * they come within an epsilon of the value, which can be an ulp off; the shortest of
 * %.15g/%.16g/%.17g that strtod maps back exactly is used instead.
 */
static cJSON *num(double v)
{
	char buf[40];

	for (int digits = 15; digits <= 17; digits++) {
		snprintf(buf, sizeof(buf), "%.*g", digits, v);
		if (strtod(buf, NULL) == v)
			break;
	}
	return cJSON_CreateRaw(buf);
}

static cJSON *vec3(const double v[3])
{
	cJSON *arr = cJSON_CreateArray();

	for (int k = 0; arr != NULL && k < 3; k++)
		cJSON_AddItemToArray(arr, num(v[k]));
	return arr;
}

static void add_num(cJSON *obj, const char *key, double v)
{
	cJSON_AddItemToObject(obj, key, num(v));
}

enum rs_status rs_load_view_format(const struct rs_scene *scene, char **out_text,
                                   struct rs_error *err)
{
	struct rs_camera cam;
	struct rs_environment env;
	const struct rs_light *lights = rs_scene_lights(scene);
	cJSON *root = cJSON_CreateObject();
	cJSON *c, *arr, *faces;

	*out_text = NULL;
	if (root == NULL)
		goto oom;
	rs_camera_resolve(rs_scene_camera(scene), &cam);
	rs_scene_environment(scene, &env);
	cJSON_AddStringToObject(root, "format", VIEW_FORMAT);
	add_num(root, "version", VIEW_VERSION);
	c = cJSON_AddObjectToObject(root, "camera");
	if (c == NULL)
		goto oom;
	cJSON_AddItemToObject(c, "eye", vec3(cam.eye));
	cJSON_AddItemToObject(c, "target", vec3(cam.target));
	cJSON_AddItemToObject(c, "up", vec3(cam.up));
	add_num(c, "fov_y_deg", cam.fov_y_deg);
	add_num(c, "width", cam.width);
	add_num(c, "height", cam.height);
	arr = cJSON_AddArrayToObject(root, "lights");
	if (arr == NULL)
		goto oom;
	for (size_t i = 0; i < rs_scene_light_count(scene); i++) {
		cJSON *l = cJSON_CreateObject();

		if (l == NULL)
			goto oom;
		cJSON_AddItemToArray(arr, l);
		cJSON_AddItemToObject(l, "position", vec3(lights[i].position));
		cJSON_AddItemToObject(l, "color", vec3(lights[i].color));
	}
	add_num(root, "ambient", rs_scene_ambient(scene));
	c = cJSON_AddObjectToObject(root, "environment");
	if (c == NULL)
		goto oom;
	cJSON_AddItemToObject(c, "center", vec3(env.center));
	add_num(c, "half_size", env.half_size);
	faces = cJSON_AddArrayToObject(c, "face_colors");
	if (faces == NULL)
		goto oom;
	for (int i = 0; i < 6; i++) {
		double rgb[3] = {env.face_color[i][0], env.face_color[i][1], env.face_color[i][2]};

		cJSON_AddItemToArray(faces, vec3(rgb));
	}
	add_num(c, "grid", env.grid);
	add_num(c, "line_width", env.line_width);
	add_num(c, "line_scale", env.line_scale);
	*out_text = cJSON_Print(root);
	cJSON_Delete(root);
	if (*out_text == NULL)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "view file: out of memory");
	return RS_OK;
oom:
	cJSON_Delete(root);
	return rs_error_set(err, RS_ERR_NO_MEMORY, "view file: out of memory");
}
