/* The renderer object: descriptor defaults in one place, the camera and size rules, stats
 * and the last error, in front of whichever backend's table of operations. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

struct rs_renderer {
	const struct rs_renderer_ops *ops;
	void *impl;
	struct rs_render_desc desc;  /* resolved; size fixed at set_scene */
	struct rs_render_desc asked; /* as given: a 0 size follows each new scene's camera */
	const struct rs_scene *scene;
	struct rs_render_stats stats;
	struct rs_error error;
	/* What update_instances may not change, as of the last set_scene or update: the
	 * prototype count and each instance's prototype, material and first triangle (kept
	 * here, since the caller may change the current scene itself before the update). */
	size_t prototype_count, instance_count;
	uint32_t *instance_keys; /* 3 per instance */
	uint64_t plain_hash;     /* of the plain (non-instance) vertices: they may not move */
};

static uint64_t fnv1a(uint64_t h, const void *data, size_t bytes)
{
	const unsigned char *p = data;
	for (size_t i = 0; i < bytes; i++)
		h = (h ^ p[i]) * 1099511628211ull;
	return h;
}

/* A hash of the positions and normals of the vertices outside every instance (an instance's
 * baked vertices are one run, runs in instance order): O(those vertices + instances). */
static uint64_t plain_vertices_hash(const struct rs_scene *scene)
{
	const double *pos = rs_scene_positions_f64(scene);
	const float *nrm = rs_scene_normals(scene);
	const uint32_t *idx = rs_scene_indices(scene);
	const struct rs_scene_instance *inst = rs_scene_instances(scene);
	uint64_t h = 14695981039346656037ull;
	size_t v = 0, n = rs_scene_instance_count(scene);
	for (size_t i = 0; i <= n; i++) {
		size_t start = rs_scene_vertex_count(scene), count = 0;
		if (i < n) {
			struct rs_mesh_desc proto;
			rs_scene_prototype_mesh(scene, inst[i].mesh, &proto);
			start = idx[(size_t)inst[i].first_triangle * 3] - proto.indices[0];
			count = proto.vertex_count;
		}
		h = fnv1a(h, pos + v * 3, (start - v) * 3 * sizeof *pos);
		h = fnv1a(h, nrm + v * 3, (start - v) * 3 * sizeof *nrm);
		v = start + count;
	}
	return h;
}

/* Remember the instances of `scene` (update_instances compares against them);
 * `plain_hash`: plain_vertices_hash(scene) where the caller has it, else 0. */
static enum rs_status keep_instances(struct rs_renderer *r, const struct rs_scene *scene,
                                     uint64_t plain_hash, struct rs_error *err)
{
	size_t n = rs_scene_instance_count(scene);
	if (n > r->instance_count || !r->instance_keys) {
		uint32_t *keys = realloc(r->instance_keys, (n ? n : 1) * 3 * sizeof *keys);
		if (!keys)
			return rs_error_set(err, RS_ERR_NO_MEMORY,
			                    "render: out of memory for the instance list");
		r->instance_keys = keys;
	}
	const struct rs_scene_instance *inst = rs_scene_instances(scene);
	for (size_t i = 0; i < n; i++) {
		r->instance_keys[i * 3] = inst[i].mesh;
		r->instance_keys[i * 3 + 1] = inst[i].material;
		r->instance_keys[i * 3 + 2] = inst[i].first_triangle;
	}
	r->instance_count = n;
	r->prototype_count = rs_scene_prototype_count(scene);
	r->plain_hash = !n ? 0 : plain_hash ? plain_hash : plain_vertices_hash(scene);
	return RS_OK;
}

void rs_render_copy_name(char *dst, size_t cap, const char *src)
{
	if (!cap)
		return;
	size_t n = src ? strlen(src) : 0;
	if (n >= cap)
		n = cap - 1;
	if (n)
		memcpy(dst, src, n);
	dst[n] = '\0';
}

enum rs_status rs_render_desc_resolve(const struct rs_render_desc *desc, struct rs_render_desc *out,
                                      struct rs_error *err)
{
	RS_ASSERT(out);
	static const struct rs_render_desc zero_desc;
	struct rs_render_desc d = desc ? *desc : zero_desc;
	if ((d.width == 0) != (d.height == 0))
		return rs_error_set(err, RS_ERR_INVALID, "render: size %ux%u has a zero side",
		                    d.width, d.height);
	if (d.width > 16384 || d.height > 16384)
		return rs_error_set(err, RS_ERR_LIMIT, "render: image %ux%u is too large (16384)",
		                    d.width, d.height);
	if (d.passes == 0)
		d.passes = 2;
	if (d.hits_only && d.counters)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "render: hits_only counts nothing (counters are for frames)");
	if (d.hits_only) { /* nothing shades: one segment, nothing captured */
		d.passes = 1;
		d.shadows = RS_SHADOW_RAYS;
		d.reflections = RS_REFLECT_TRACE;
	}
	if (d.passes > RS_TRACE_MAX_PASSES)
		return rs_error_set(err, RS_ERR_INVALID, "render: %u passes (at most %u)", d.passes,
		                    RS_TRACE_MAX_PASSES);
	if (d.triangle_test != RS_TRIANGLE_MOLLER_TRUMBORE &&
	    d.triangle_test != RS_TRIANGLE_WATERTIGHT)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown triangle test %d",
		                    (int)d.triangle_test);
	if (!isfinite(d.ray_epsilon) || d.ray_epsilon < 0.0)
		return rs_error_set(err, RS_ERR_INVALID, "render: ray epsilon %g is not >= 0",
		                    d.ray_epsilon);
	if (d.primary != RS_PRIMARY_TRACE && d.primary != RS_PRIMARY_RASTER)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown primary mode %d",
		                    (int)d.primary);
	if (d.shadows != RS_SHADOW_RAYS && d.shadows != RS_SHADOW_MAP &&
	    d.shadows != RS_SHADOW_NONE)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown shadow mode %d",
		                    (int)d.shadows);
	if (d.reflections != RS_REFLECT_TRACE && d.reflections != RS_REFLECT_ENVMAP &&
	    d.reflections != RS_REFLECT_INTERREFLECT)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown reflection mode %d",
		                    (int)d.reflections);
	if (d.envmap_size == 0)
		d.envmap_size = RS_RENDER_ENVMAP_SIZE;
	if (d.envmap_size > RS_RENDER_MAX_ENVMAP_SIZE)
		return rs_error_set(
		    err, RS_ERR_LIMIT,
		    "render: environment map face side %u is too large (at most %u)", d.envmap_size,
		    RS_RENDER_MAX_ENVMAP_SIZE);
	if (d.reflection_bounces == 0)
		d.reflection_bounces = 1;
	if (d.reflection_bounces > RS_RENDER_MAX_BOUNCES)
		return rs_error_set(err, RS_ERR_INVALID, "render: %u reflection bounces (1..%u)",
		                    d.reflection_bounces, RS_RENDER_MAX_BOUNCES);
	if (d.chain != RS_CHAIN_FUSED && d.chain != RS_CHAIN_SEPARATE && d.chain != RS_CHAIN_PAPER)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown kernel chain %d",
		                    (int)d.chain);
	if (d.kernels != RS_KERNELS_FRAGMENT && d.kernels != RS_KERNELS_COMPUTE)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown kernel stage %d",
		                    (int)d.kernels);
	if (d.scene_storage != RS_SCENE_STORAGE_AUTO && d.scene_storage != RS_SCENE_STORAGE_2D &&
	    d.scene_storage != RS_SCENE_STORAGE_BUFFER)
		return rs_error_set(err, RS_ERR_INVALID, "render: unknown scene storage %d",
		                    (int)d.scene_storage);
	if (d.shadow_map_size == 0)
		d.shadow_map_size = 512;
	if (d.shadow_map_size > 16384)
		return rs_error_set(err, RS_ERR_LIMIT, "render: shadow map side %u is too large",
		                    d.shadow_map_size);
	if (d.shadow_filter == 0)
		d.shadow_filter = 3;
	if (d.shadow_filter > d.shadow_map_size)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "render: shadow filter %u is wider than the %u-texel map",
		                    d.shadow_filter, d.shadow_map_size);
	if (d.pack.max_texture_size && d.pack.max_texture_size < RS_PACK_MAX_ITEM_TEXELS)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "render: a texture size limit of %u texels cannot hold one "
		                    "%u-texel item",
		                    d.pack.max_texture_size, RS_PACK_MAX_ITEM_TEXELS);
	/* With the limit left to the device, a row width is checked when the device is known. */
	if (d.pack.max_texture_size &&
	    d.pack.row_items > d.pack.max_texture_size / RS_PACK_MAX_ITEM_TEXELS)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "render: %u items per texture row do not fit a %u-texel row",
		                    d.pack.row_items, d.pack.max_texture_size);
	if (isnan(d.rebuild_ratio) || d.rebuild_ratio < 0.0)
		return rs_error_set(err, RS_ERR_INVALID, "render: rebuild ratio %g is not >= 0",
		                    d.rebuild_ratio);
	if (d.threads > RS_RENDER_MAX_THREADS)
		return rs_error_set(err, RS_ERR_INVALID, "render: %u threads (at most %u)",
		                    d.threads, RS_RENDER_MAX_THREADS);
	*out = d;
	return RS_OK;
}

void rs_render_stats_finish(struct rs_render_stats *stats)
{
	RS_ASSERT(stats);
	double px = (double)stats->pixels;
	stats->box_per_pixel = px > 0 ? (double)stats->box_tests / px : 0.0;
	stats->triangle_per_pixel = px > 0 ? (double)stats->triangle_tests / px : 0.0;
	stats->total_per_pixel = stats->box_per_pixel + stats->triangle_per_pixel;
}

enum rs_status rs_renderer_create(const struct rs_renderer_ops *ops, void *impl,
                                  const struct rs_render_desc *desc, struct rs_renderer **out,
                                  struct rs_error *err)
{
	RS_ASSERT(ops && ops->set_scene && ops->render && ops->destroy && out);
	*out = NULL;
	struct rs_renderer *r = calloc(1, sizeof *r);
	enum rs_status status =
	    r ? rs_render_desc_resolve(desc, &r->desc, err)
	      : rs_error_set(err, RS_ERR_NO_MEMORY, "render: out of memory for a renderer");
	if (status != RS_OK) {
		free(r);
		ops->destroy(impl);
		return status;
	}
	r->asked = r->desc;
	r->ops = ops;
	r->impl = impl;
	rs_render_copy_name(r->stats.backend, sizeof r->stats.backend, ops->name);
	if (ops->describe)
		ops->describe(impl, r->stats.renderer, sizeof r->stats.renderer);
	*out = r;
	return RS_OK;
}

void rs_renderer_destroy(struct rs_renderer **renderer)
{
	if (!renderer || !*renderer)
		return;
	struct rs_renderer *r = *renderer;
	r->ops->destroy(r->impl);
	free(r->instance_keys);
	free(r);
	*renderer = NULL;
}

/* Record a failure as the renderer's last error and hand it to the caller's err too. */
static enum rs_status fail(struct rs_renderer *r, enum rs_status status, struct rs_error *err)
{
	if (err)
		*err = r->error;
	return status;
}

enum rs_status rs_renderer_set_scene(struct rs_renderer *renderer, const struct rs_scene *scene,
                                     struct rs_error *err)
{
	RS_ASSERT(renderer && scene);
	struct rs_renderer *r = renderer;
	rs_error_clear(&r->error);
	struct rs_render_desc d = r->asked;
	if (d.width == 0) {
		struct rs_camera cam;
		rs_camera_resolve(rs_scene_camera(scene), &cam);
		d.width = cam.width;
		d.height = cam.height;
	}
	if (d.lights > rs_scene_light_count(scene))
		return fail(r,
		            rs_error_set(&r->error, RS_ERR_INVALID,
		                         "render: %u lights asked, the scene has %zu", d.lights,
		                         rs_scene_light_count(scene)),
		            err);
	/* A failed upload leaves no scene behind: rendering the previous one would show a
	 * picture of something the caller replaced. */
	r->scene = NULL;
	struct rs_render_stats stats = {0};
	memcpy(stats.backend, r->stats.backend, sizeof stats.backend);
	memcpy(stats.renderer, r->stats.renderer, sizeof stats.renderer);
	stats.width = d.width;
	stats.height = d.height;
	enum rs_status status = r->ops->set_scene(r->impl, scene, &d, &stats, &r->error);
	r->stats = stats;
	if (status == RS_OK)
		status = keep_instances(r, scene, 0, &r->error);
	if (status != RS_OK)
		return fail(r, status, err);
	r->desc = d;
	r->scene = scene;
	return RS_OK;
}

/* update_vertices and update_instances: `op` moves the backend to `scene`, whose topology
 * (and instances, for update_instances) the caller checked; `plain_hash` as keep_instances
 * takes it. */
static enum rs_status update(struct rs_renderer *r, const struct rs_scene *scene,
                             enum rs_status (*op)(void *, const struct rs_scene *,
                                                  struct rs_render_stats *, struct rs_error *),
                             uint64_t plain_hash, struct rs_error *err)
{
	struct rs_render_stats *s = &r->stats;
	s->update_rebuilt = false;
	s->update_sah_ratio = s->refit_ms = s->build_ms = s->pack_ms = s->upload_ms = 0.0;
	s->tlas_build_ms = 0.0;
	s->upload_bytes = 0;
	enum rs_status status = op(r->impl, scene, s, &r->error);
	/* as set_scene: a failed update leaves no scene to render, unless the backend refused
	 * before touching anything (RS_ERR_UNSUPPORTED) */
	if (status == RS_OK)
		status = keep_instances(r, scene, plain_hash, &r->error);
	if (status != RS_ERR_UNSUPPORTED)
		r->scene = status == RS_OK ? scene : NULL;
	if (status != RS_OK)
		return fail(r, status, err);
	s->updates++;
	s->update_rebuilds += s->update_rebuilt ? 1u : 0u;
	return RS_OK;
}

/* The checks both updates start with: a scene is set and the backend can update. */
static enum rs_status can_update(struct rs_renderer *r, const struct rs_scene *scene,
                                 bool instances, struct rs_error *err)
{
	rs_error_clear(&r->error);
	if (!r->scene)
		return fail(r, rs_error_set(&r->error, RS_ERR_INVALID, "render: no scene set"),
		            err);
	if (!r->ops->update_vertices && !(instances && r->ops->update_instances))
		return fail(r,
		            rs_error_set(&r->error, RS_ERR_UNSUPPORTED,
		                         "render: the %s backend cannot update %s", r->ops->name,
		                         instances ? "instances" : "vertices"),
		            err);
	enum rs_status status = rs_render_scene_same_topology(r->scene, scene, &r->error);
	return status == RS_OK ? RS_OK : fail(r, status, err);
}

enum rs_status rs_renderer_update_vertices(struct rs_renderer *renderer,
                                           const struct rs_scene *scene, struct rs_error *err)
{
	RS_ASSERT(renderer && scene);
	enum rs_status status = can_update(renderer, scene, false, err);
	return status == RS_OK ? update(renderer, scene, renderer->ops->update_vertices, 0, err)
	                       : status;
}

enum rs_status rs_renderer_update_instances(struct rs_renderer *renderer,
                                            const struct rs_scene *scene, struct rs_error *err)
{
	RS_ASSERT(renderer && scene);
	struct rs_renderer *r = renderer;
	enum rs_status status = can_update(r, scene, true, err);
	if (status != RS_OK)
		return status;
	const char *what = NULL;
	size_t n = rs_scene_instance_count(scene);
	const struct rs_scene_instance *inst = rs_scene_instances(scene);
	if (n == 0)
		what = "the scene has no instances";
	else if (n != r->instance_count)
		what = "the instance count changed";
	else if (rs_scene_prototype_count(scene) != r->prototype_count)
		what = "the prototype count changed";
	for (size_t i = 0; !what && i < n; i++)
		if (inst[i].mesh != r->instance_keys[i * 3] ||
		    inst[i].material != r->instance_keys[i * 3 + 1] ||
		    inst[i].first_triangle != r->instance_keys[i * 3 + 2])
			what = "an instance's prototype, material or triangles changed";
	/* the plain vertices are hashed once a frame: checked here, kept by update() */
	uint64_t plain_hash = what ? 0 : plain_vertices_hash(scene);
	if (!what && plain_hash != r->plain_hash)
		what = "plain (non-instance) vertices moved";
	if (what)
		return fail(r,
		            rs_error_set(&r->error, RS_ERR_INVALID,
		                         "render: update_instances: %s (only transforms may; "
		                         "set_scene the new scene)",
		                         what),
		            err);
	bool baked = !r->ops->update_instances;
	/* an op may say it took the baked path too (a renderer drawing the scene flattened) */
	r->stats.instance_update_baked = false;
	status = update(r, scene, baked ? r->ops->update_vertices : r->ops->update_instances,
	                plain_hash, err);
	if (status == RS_OK) {
		r->stats.instance_updates++;
		r->stats.instance_update_baked |= baked;
	}
	return status;
}

enum rs_status rs_renderer_render(struct rs_renderer *renderer, const struct rs_camera *camera,
                                  const struct rs_frame *frame, struct rs_error *err)
{
	RS_ASSERT(renderer && frame);
	struct rs_renderer *r = renderer;
	rs_error_clear(&r->error);
	if (!r->scene)
		return fail(r, rs_error_set(&r->error, RS_ERR_INVALID, "render: no scene set"),
		            err);
	struct rs_camera cam;
	if (camera) {
		enum rs_status status = rs_camera_check(camera, &r->error);
		if (status != RS_OK)
			return fail(r, status, err);
		rs_camera_resolve(camera, &cam);
	} else {
		rs_camera_resolve(rs_scene_camera(r->scene), &cam);
	}
	if (r->desc.hits_only && (frame->rgb || frame->rgba8))
		return fail(r,
		            rs_error_set(&r->error, RS_ERR_INVALID,
		                         "render: a hits_only renderer has no colour (rgb, rgba8)"),
		            err);
	cam.width = r->desc.width;
	cam.height = r->desc.height;
	struct rs_render_stats *s = &r->stats;
	s->pixels = s->primary_rays = s->secondary_rays = s->shadow_rays = 0;
	s->box_tests = s->triangle_tests = 0;
	s->counters_valid = false;
	s->render_ms = s->readback_ms = 0.0;
	s->kernel_count = 0;
	enum rs_status status = r->ops->render(r->impl, &cam, frame, s, &r->error);
	rs_render_stats_finish(s);
	return status == RS_OK ? RS_OK : fail(r, status, err);
}

const struct rs_render_desc *rs_renderer_desc(const struct rs_renderer *renderer)
{
	RS_ASSERT(renderer);
	return &renderer->desc;
}

const struct rs_render_stats *rs_renderer_stats(const struct rs_renderer *renderer)
{
	RS_ASSERT(renderer);
	return &renderer->stats;
}

const char *rs_renderer_last_error(const struct rs_renderer *renderer)
{
	RS_ASSERT(renderer);
	return renderer->error.message;
}

const char *rs_renderer_backend(const struct rs_renderer *renderer)
{
	RS_ASSERT(renderer);
	return renderer->ops->name;
}
