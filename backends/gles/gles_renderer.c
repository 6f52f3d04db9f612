/* The GLES renderer object, the top of the backend's stack (gles_internal.h): the ops table,
 * the capability probe at creation; per scene the frame description, the plans, the
 * kernels specialised for the scene (lights, whether any material reflects or refracts,
 * triangle test, counters), the upload and the captures; per frame the captures that
 * change, the frame's plan (its last pass writing the RGBA8 colour, or the display pass
 * after it: displayed()) and the readback. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gles_internal.h"
#include "gles_seams.h"

/* R7 (docs/tracer.md): the kernels compute in fp32, whose range a frame must stay within:
 * one that reaches too far (or stays too near its centre) is refused, never drawn wrong.
 * `eye` in the packed frame. */
static enum rs_status check_reach(const struct rs_trace_frame *f, const double eye[3],
                                  struct rs_error *err)
{
	double reach = rs_trace_frame_reach(f, eye);
	if (reach == 0.0 || (reach >= RS_TRACE_FP32_REACH_MIN && reach <= RS_TRACE_FP32_REACH_MAX))
		return RS_OK;
	return rs_error_set(err, RS_ERR_LIMIT,
	                    "gles: the frame reaches %.3g units from the scene's centre (camera, "
	                    "lights and environment box included); the fp32 kernels need %.3g to "
	                    "%.3g: scale the scene, or render it on the cpu backend",
	                    reach, RS_TRACE_FP32_REACH_MIN, RS_TRACE_FP32_REACH_MAX);
}

/* Refuse what this GL cannot hold, naming the limit (GLES 3.0 guarantees only 2048). 2D
 * storage only: buffer textures have no rows (rs_gles_choose_storage checked their length). */
static enum rs_status check_limits(const struct gles *g, const struct rs_packed *p,
                                   const struct rs_trace_frame *f, struct rs_error *err)
{
	const struct rs_render_desc *d = &g->desc;
	const struct rs_texture *t[4] = {&p->nodes, &p->triangles, &p->normals, &p->materials};
	static const char *const names[4] = {"node", "triangle", "normal", "material"};
	for (int i = 0; g->storage == RS_SCENE_STORAGE_2D && i < 4; ++i)
		if (t[i]->width > (uint32_t)g->max_tex || t[i]->height > (uint32_t)g->max_tex)
			return rs_error_set(
			    err, RS_ERR_LIMIT,
			    "gles: the scene's %s texture is %ux%u texels, over this "
			    "GL's GL_MAX_TEXTURE_SIZE of %d",
			    names[i], t[i]->width, t[i]->height, g->max_tex);
	GLint side = g->max_tex < g->max_view ? g->max_tex : g->max_view;
	if (d->width > (uint32_t)side || d->height > (uint32_t)side)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "gles: image %ux%u is over this GL's limit of %d texels a side",
		                    d->width, d->height, side);
	if (d->reflections != RS_REFLECT_TRACE && g->face_size > (uint32_t)side)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "gles: environment map face side %u is over this GL's limit of "
		                    "%d texels",
		                    g->face_size, side);
	if (d->shadows == RS_SHADOW_MAP && d->shadow_map_size > (uint32_t)g->max_tex)
		return rs_error_set(
		    err, RS_ERR_LIMIT,
		    "gles: shadow map side %u is over this GL's GL_MAX_TEXTURE_SIZE "
		    "of %d",
		    d->shadow_map_size, g->max_tex);
	if (f->light_count > RS_GLES_MAX_LIGHTS)
		return rs_error_set(err, RS_ERR_LIMIT, "gles: %u lights (the kernels take %u)",
		                    f->light_count, RS_GLES_MAX_LIGHTS);
	/* the scene alone (seen from its centre; each frame checks its own camera) */
	return check_reach(f, f->bounds_center, err);
}

static bool scene_has_optics(const struct rs_scene *scene)
{
	const struct rs_material *m = rs_scene_materials(scene);
	for (size_t i = 0; i < rs_scene_material_count(scene); ++i)
		if (m[i].reflectance > 0.0f || m[i].transmittance > 0.0f)
			return true;
	return false;
}

/* The layout this GL can hold: the descriptor's texture limit, or GL_MAX_TEXTURE_SIZE when
 * it leaves it to the device; a limit above the device's is refused, naming both. */
static enum rs_status pack_desc(const struct gles *g, const struct rs_render_desc *desc,
                                struct rs_pack_desc *out, struct rs_error *err)
{
	*out = desc->pack;
	if (!out->max_texture_size)
		out->max_texture_size = (uint32_t)g->max_tex;
	if (out->max_texture_size > (uint32_t)g->max_tex)
		return rs_error_set(err, RS_ERR_LIMIT,
		                    "gles: a texture size limit of %u texels is over this GL's "
		                    "GL_MAX_TEXTURE_SIZE of %d",
		                    out->max_texture_size, g->max_tex);
	return RS_OK;
}

/* log2 of a power of two, else -1 (the kernels then divide). */
static int row_shift(uint32_t items)
{
	for (int s = 0; s < 31; ++s)
		if ((1u << s) == items)
			return s;
	return -1;
}

/* The three #define preludes (every program, the fused first pass, it over raster hits) and
 * the programs the plans use. */
static enum rs_status build_programs(struct gles *g, struct rs_error *err)
{
	const struct rs_packed *p = &g->accel.packed;
	struct rs_gles_spec spec = {
	    .row_items = p->row_items,
	    .row_shift = row_shift(p->row_items),
	    .lights = g->frame.light_count,
	    /* two levels: every tree's orders (the merged texture counts items, one "order") */
	    .node_orders =
	        g->accel.two_level.instance_count ? g->accel.two_level.tree_orders : p->node_orders,
	    .watertight = g->desc.triangle_test == RS_TRIANGLE_WATERTIGHT,
	    .counters = g->desc.counters,
	    .optics = scene_has_optics(g->scene),
	    .geometry = g->frame.has_geometry,
	    .shadow_map = g->desc.shadows == RS_SHADOW_MAP,
	    .unshadowed = g->frame.unshadowed, /* the reference's decision, not a second one */
	    .envmap = g->desc.reflections != RS_REFLECT_TRACE,
	    .interreflect = g->desc.reflections == RS_REFLECT_INTERREFLECT,
	    .compact_nodes = p->node_format == RS_PACK_NODES_COMPACT,
	    .wide_nodes = p->node_format == RS_PACK_NODES_WIDE4,
	    .scene_buffers = g->storage == RS_SCENE_STORAGE_BUFFER,
	    .two_level = g->accel.two_level.instance_count > 0,
	    .instance_row_items = g->accel.two_level.instance_row_items,
	};
	char preludes[3][1024];
	enum rs_status st = RS_OK;
	for (int v = 0; st == RS_OK && v < 3; ++v) {
		spec.first_pass = v >= 1;
		spec.raster_first = v == 2;
		st = rs_gles_prelude(&spec, &g->frame.rules, preludes[v], sizeof preludes[v], err);
	}
	const char *const list[3] = {preludes[0], preludes[1], preludes[2]};
	return st == RS_OK ? rs_gles_programs_build(g, list, err) : st;
}

/* The frame's plan and the capture frames' (decided here, once per scene). */
static void make_plans(struct gles *g)
{
	const struct rs_render_desc *d = &g->desc;
	struct rs_gles_plan_desc pd = {.passes = d->passes,
	                               .primary = d->primary,
	                               .chain = d->chain,
	                               .counters = d->counters,
	                               .envmap = d->reflections != RS_REFLECT_TRACE,
	                               .hits_only = d->hits_only,
	                               .compute = d->kernels == RS_KERNELS_COMPUTE};
	rs_gles_plan_make(&pd, &g->plans[PLAN_FRAME]);
	if (!pd.envmap)
		return;
	/* the classic map: what the centre sees directly, with the frame's primaries */
	pd.passes = 1;
	rs_gles_plan_make(&pd, &g->plans[PLAN_ENVMAP]);
	if (d->reflections != RS_REFLECT_INTERREFLECT)
		return;
	/* the objects' maps: rays start on a sphere, which a raster pass cannot do */
	pd.primary = RS_PRIMARY_TRACE;
	rs_gles_plan_make(&pd, &g->plans[PLAN_BOUNCE_1]);
	pd.passes = 2;
	rs_gles_plan_make(&pd, &g->plans[PLAN_BOUNCE_N]);
}

/* The captures set_scene makes and the warm-up: the whole chain once on a 1x1 viewport,
 * results unused (drivers such as llvmpipe compile a kernel at its first draw, which would
 * otherwise land in the first frame's timings). */
static enum rs_status prepare(struct gles *g, struct rs_error *err)
{
	enum rs_status st = RS_OK;
	if (g->desc.shadows == RS_SHADOW_MAP)
		st = rs_gles_shadow_maps(g, err);
	/* Inter-reflection: rays that leave no mirror object read the classic map. */
	if (st == RS_OK && g->desc.reflections != RS_REFLECT_TRACE)
		st = rs_gles_envmap(g, err);
	if (st == RS_OK && g->desc.reflections == RS_REFLECT_INTERREFLECT)
		st = rs_gles_interreflect_setup(g, err);
	struct rs_camera cam;
	rs_camera_resolve(rs_scene_camera(g->scene), &cam);
	struct rs_render_stats stats = {0};
	const struct rs_gles_plan *plan = &g->plans[PLAN_FRAME];
	if (st == RS_OK)
		st = rs_gles_plan_run(g, plan, &cam, 0.0f, 1, 1, false, &stats, err);
	if (st == RS_OK)
		st = rs_gles_display(g, plan, &stats, err);
	/* ... and displayed (gles_render's other way to a frame): the last pass then draws into
	 * other targets, for which llvmpipe compiles a variant of its program at its first draw */
	if (st == RS_OK && rs_gles_plan_displays(plan))
		st = rs_gles_plan_run(g, plan, &cam, 0.0f, 1, 1, true, &stats, err);
	return st;
}

/* The scene textures' bytes (and two levels: the instance texture's). */
static uint64_t scene_bytes(const struct rs_render_accel *a)
{
	const struct rs_packed *p = &a->packed;
	const struct rs_texture *t[4] = {&p->nodes, &p->triangles, &p->normals, &p->materials};
	const struct rs_texture *inst = &a->two_level.instances;
	uint64_t n = a->two_level.instance_count ? (uint64_t)inst->width * inst->height * 16u : 0;
	for (int i = 0; i < 4; ++i)
		n += (uint64_t)t[i]->width * t[i]->height * 16u;
	return n;
}

/* The most texels one scene texture of this GL may hold (2D or buffer storage). */
static uint64_t max_texels(const struct gles *g)
{
	uint64_t side = (uint64_t)g->max_tex * (uint64_t)g->max_tex;
	uint64_t buf = g->buffer_glsl ? (uint64_t)g->max_tex_buffer : 0u;
	return side > buf ? side : buf;
}

/* set_scene; `moving`: asked by an instance update (rs_gles_two_level). */
static enum rs_status set_scene(struct gles *g, const struct rs_scene *scene,
                                const struct rs_render_desc *desc, bool moving,
                                struct rs_render_stats *stats, struct rs_error *err)
{
	enum rs_status st = g->cops->make_current(g->ctx, err);
	if (st != RS_OK)
		return st;
	if (desc->hits_only && g->cops->display_target) {
		g->cops->release(g->ctx);
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: hits_only has no image for the window to show");
	}
	if (desc->kernels == RS_KERNELS_COMPUTE &&
	    (!g->compute_glsl || desc->chain != RS_CHAIN_FUSED)) {
		g->cops->release(g->ctx);
		if (desc->chain != RS_CHAIN_FUSED)
			return rs_error_set(
			    err, RS_ERR_UNSUPPORTED,
			    "gles: kernels compute runs the fused chain only (chain "
			    "fused)");
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: kernels compute needs GLES 3.1 compute shaders with 4 "
		                    "image units, which %s lacks (kernels fragment runs here)",
		                    g->renderer);
	}
	rs_gles_scene_delete(g);
	g->desc = *desc;
	g->scene = scene;
	g->face_size = desc->envmap_size ? desc->envmap_size : RS_RENDER_ENVMAP_SIZE;
	struct rs_pack_desc pack;
	st = pack_desc(g, desc, &pack, err);
	struct rs_bvh_desc bvh = rs_render_bvh_desc(desc);
	bool two_level = false;
	if (st == RS_OK)
		st = rs_gles_two_level(desc, scene, moving, max_texels(g), &two_level, err);
	if (st == RS_OK)
		st = two_level ? rs_render_accel_build_two_level(scene, &bvh, &pack, &g->accel, err)
		               : rs_render_accel_build(scene, &bvh, &pack, &g->accel, err);
	struct rs_trace_desc td = rs_render_trace_desc(desc);
	td.two_level = two_level && st == RS_OK ? &g->accel.two_level : NULL;
	if (st == RS_OK)
		st = rs_trace_frame_init(scene, &g->accel.packed, &td, &g->frame, err);
	if (st == RS_OK)
		st = rs_gles_choose_storage(g, &g->accel.packed,
		                            td.two_level ? &g->accel.two_level.instances : NULL,
		                            desc->scene_storage, err);
	if (st == RS_OK)
		st = check_limits(g, &g->accel.packed, &g->frame, err);
	if (st == RS_OK)
		stats->scene_storage = g->storage;
	/* The readback's scratch also holds a cube face where faces take the fallback. */
	uint32_t face = desc->reflections != RS_REFLECT_TRACE ? g->face_size : 0;
	size_t floats = (size_t)(desc->width > face ? desc->width : face) *
	                (desc->height > face ? desc->height : face) * 4u;
	if (st == RS_OK && !(g->scratch = malloc(floats * sizeof(float))))
		st = rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory for %ux%u",
		                  desc->width, desc->height);
	if (st == RS_OK)
		make_plans(g);
	/* upload_ms: the kernels' compile and the textures' upload, nothing else */
	double t0 = rs_now_ms();
	if (st == RS_OK)
		st = build_programs(g, err);
	if (st == RS_OK)
		st = rs_gles_scene_upload(g, err);
	if (st == RS_OK) {
		g->gl.Finish();
		stats->upload_ms = rs_now_ms() - t0;
		st = prepare(g, err);
	}
	if (st == RS_OK) {
		g->gl.Finish();
		stats->upload_bytes = scene_bytes(&g->accel);
		stats->build_ms = g->accel.build_ms;
		stats->pack_ms = g->accel.pack_ms;
	} else {
		rs_gles_scene_delete(g);
	}
	g->cops->release(g->ctx);
	return st;
}

static enum rs_status gles_set_scene(void *impl, const struct rs_scene *scene,
                                     const struct rs_render_desc *desc,
                                     struct rs_render_stats *stats, struct rs_error *err)
{
	return set_scene(impl, scene, desc, false, stats, err);
}

/* The one decision of a frame's way to RGBA8: the last trace pass writes the bytes itself
 * (a displayed run, rs_gles_step.display; no display pass) where the plan can and nothing
 * reads the float colour after it: no float readback (rs_frame.rgb) and no window (its
 * present and refinement read the float colour). Else the display pass, when RGBA8 is
 * asked for. On llvmpipe a classic environment-map frame takes 0.96-0.98x the time
 * (docs/benchmarks.md, "The display pass fused into the last trace pass"). */
static bool displayed(const struct gles *g, const struct rs_gles_plan *plan,
                      const struct rs_frame *frame)
{
	/* test builds only (gles_seams.h): the display pass forced, to compare both ways */
	if (rs__gles_display_unfused && rs__gles_display_unfused())
		return false;
	return frame->rgba8 && !frame->rgb && !g->cops->display_target &&
	       rs_gles_plan_displays(plan);
}

static enum rs_status gles_render(void *impl, const struct rs_camera *camera,
                                  const struct rs_frame *frame, struct rs_render_stats *stats,
                                  struct rs_error *err)
{
	struct gles *g = impl;
	double eye[3];
	for (int a = 0; a < 3; ++a)
		eye[a] = camera->eye[a] - g->frame.origin[a];
	enum rs_status st = check_reach(&g->frame, eye, err);
	if (st != RS_OK)
		return st;
	st = g->cops->make_current(g->ctx, err);
	if (st != RS_OK)
		return st;
	/* Inter-reflection maps are dynamic: captured for every frame (and counted in its time,
	 * which is what Table 3 compares); a 1-pass frame reads none. */
	double t0 = rs_now_ms(), capture_ms = 0.0;
	if (g->desc.reflections == RS_REFLECT_INTERREFLECT && g->desc.passes > 1) {
		st = rs_gles_interreflect_capture(g, err);
		capture_ms = rs_now_ms() - t0;
	}
	const struct rs_gles_plan *plan = &g->plans[PLAN_FRAME];
	bool display = displayed(g, plan, frame);
	double t1 = rs_now_ms();
	if (st == RS_OK)
		st = rs_gles_plan_run(g, plan, camera, 0.0f, (GLsizei)g->desc.width,
		                      (GLsizei)g->desc.height, display, stats, err);
	/* Else the display pass is a step of its own: RGBA8 is made only when asked for. */
	if (st == RS_OK && frame->rgba8 && !display)
		st = rs_gles_display(g, plan, stats, err);
	stats->render_ms = rs_now_ms() - t1 + capture_ms;
	stats->pixels = (uint64_t)g->desc.width * g->desc.height;
	stats->primary_rays = stats->pixels;
	if (capture_ms > 0.0)
		rs_gles_kernel_time(stats, "envmap capture", capture_ms);
	if (st == RS_OK) {
		double t2 = rs_now_ms();
		st = rs_gles_readback(g, plan, frame, stats, err);
		stats->readback_ms = rs_now_ms() - t2;
	}
	/* A window context: the frame goes to the screen straight from the plan's colour. */
	if (st == RS_OK && g->cops->display_target)
		st = rs_gles_present(g, rs_gles_target(g, plan->result_acc), g->desc.width,
		                     g->desc.height, camera->sample, stats, err);
	g->cops->release(g->ctx);
	return st;
}

/* Everything the compiled kernels were specialised for (build_programs) is the same in
 * both frames and layouts: then the programs stay, and only texels change. */
static bool same_kernels(const struct gles *g, const struct rs_packed *p,
                         const struct rs_trace_frame *f)
{
	const struct rs_packed *q = &g->accel.packed;
	const struct rs_texture *a[4] = {&p->nodes, &p->triangles, &p->normals, &p->materials};
	const struct rs_texture *b[4] = {&q->nodes, &q->triangles, &q->normals, &q->materials};
	for (int i = 0; i < 4; ++i)
		if (a[i]->width != b[i]->width || a[i]->height != b[i]->height ||
		    a[i]->format != b[i]->format)
			return false;
	return p->row_items == q->row_items && p->node_orders == q->node_orders &&
	       p->node_format == q->node_format && f->light_count == g->frame.light_count &&
	       f->has_geometry == g->frame.has_geometry &&
	       memcmp(&f->rules, &g->frame.rules, sizeof f->rules) == 0;
}

/* Per-frame vertices: refit (or rebuild) and repack in lib/render, then send the texel rows
 * that differ from what the GPU holds. A new layout or new kernel constants (a rebuild with
 * another node count, a scene whose size changed the rules) take the set_scene path. */
static enum rs_status gles_update_vertices(void *impl, const struct rs_scene *scene,
                                           struct rs_render_stats *stats, struct rs_error *err)
{
	struct gles *g = impl;
	if (g->desc.shadows == RS_SHADOW_MAP || g->desc.reflections != RS_REFLECT_TRACE)
		return rs_error_set(
		    err, RS_ERR_UNSUPPORTED,
		    "gles: update_vertices with shadow or environment maps (captured "
		    "at set_scene): set_scene the moved scene");
	struct rs_pack_desc pack;
	enum rs_status st = pack_desc(g, &g->desc, &pack, err);
	struct rs_render_accel next = {0};
	if (st == RS_OK)
		st = rs_render_accel_update(&g->accel, scene, &g->desc.bvh, &pack,
		                            g->desc.rebuild_ratio, &next, err);
	struct rs_trace_desc td = rs_render_trace_desc(&g->desc);
	struct rs_trace_frame frame;
	td.two_level = next.two_level.instance_count ? &next.two_level : NULL;
	if (st == RS_OK)
		st = rs_trace_frame_init(scene, &next.packed, &td, &frame, err);
	/* two levels: both trees and the instance texture are new (set_scene) */
	if (st == RS_OK && (td.two_level || !same_kernels(g, &next.packed, &frame))) {
		double refit_ms = next.refit_ms, ratio = next.sah_ratio;
		rs_render_accel_free(&next);
		struct rs_render_desc d = g->desc;
		st = gles_set_scene(g, scene, &d, stats, err);
		stats->update_rebuilt = true; /* set_scene builds */
		stats->update_sah_ratio = ratio;
		stats->refit_ms = refit_ms;
		stats->upload_bytes = st == RS_OK ? scene_bytes(&g->accel) : 0;
		return st;
	}
	if (st == RS_OK)
		st = g->cops->make_current(g->ctx, err);
	if (st != RS_OK) {
		rs_render_accel_free(&next);
		return st;
	}
	double t0 = rs_now_ms();
	uint64_t bytes = 0;
	st = rs_gles_scene_update(g, &next.packed, &bytes, err);
	g->gl.Finish();
	stats->upload_ms = rs_now_ms() - t0;
	g->cops->release(g->ctx);
	if (st != RS_OK) {
		rs_render_accel_free(&next);
		return st;
	}
	rs_render_accel_free(&g->accel);
	g->accel = next;
	g->scene = scene;
	/* the frame points at the packed textures it was made from: made again on the kept ones */
	st = rs_trace_frame_init(scene, &g->accel.packed, &td, &g->frame, err);
	stats->update_rebuilt = next.rebuilt;
	stats->update_sah_ratio = next.sah_ratio;
	stats->refit_ms = next.refit_ms;
	stats->build_ms = next.rebuilt ? next.build_ms : 0.0;
	stats->pack_ms = next.pack_ms;
	stats->upload_bytes = bytes;
	return st;
}

/* Per-frame instance transforms. Two levels: the TLAS rebuilt and merged in lib/render, and
 * only its rows and the instance texture sent; flattened: the baked triangles moved. */
static enum rs_status gles_update_instances(void *impl, const struct rs_scene *scene,
                                            struct rs_render_stats *stats, struct rs_error *err)
{
	struct gles *g = impl;
	if (!g->accel.two_level.instance_count) {
		/* auto flattened a still scene: now that it moves, two levels (set once) */
		bool two_level = false;
		if (g->desc.instances == RS_INSTANCES_AUTO &&
		    rs_gles_two_level(&g->desc, scene, true, max_texels(g), &two_level, NULL) ==
		        RS_OK &&
		    two_level) {
			struct rs_render_desc desc = g->desc;
			return set_scene(g, scene, &desc, true, stats, err);
		}
		enum rs_status st = gles_update_vertices(impl, scene, stats, err);
		stats->instance_update_baked = true;
		return st;
	}
	struct rs_bvh_desc bvh = rs_render_bvh_desc(&g->desc);
	enum rs_status st = rs_render_accel_update_instances(&g->accel, scene, &bvh, err);
	struct rs_trace_desc td = rs_render_trace_desc(&g->desc);
	td.two_level = &g->accel.two_level;
	/* the TLAS frame moved with the instances: the frame is made again */
	if (st == RS_OK)
		st = rs_trace_frame_init(scene, &g->accel.packed, &td, &g->frame, err);
	if (st == RS_OK)
		st = g->cops->make_current(g->ctx, err);
	if (st != RS_OK)
		return st;
	double t0 = rs_now_ms();
	uint64_t bytes = 0;
	st = rs_gles_scene_update_top(g, &bytes, err);
	g->gl.Finish();
	stats->upload_ms = rs_now_ms() - t0;
	g->cops->release(g->ctx);
	g->scene = scene;
	stats->tlas_build_ms = g->accel.tlas_build_ms;
	stats->pack_ms = g->accel.pack_ms;
	stats->upload_bytes = bytes;
	return st;
}

static void gles_destroy(void *impl)
{
	struct gles *g = impl;
	if (!g)
		return;
	if (g->gl.DeleteTextures && g->cops->make_current(g->ctx, NULL) == RS_OK) {
		rs_gles_scene_delete(g);
		rs_gles_display_free(g);
		if (g->fbo)
			g->gl.DeleteFramebuffers(1, &g->fbo);
		if (g->vao)
			g->gl.DeleteVertexArrays(1, &g->vao);
		g->cops->release(g->ctx);
	}
	rs_render_accel_free(&g->accel);
	free(g->scratch);
	g->cops->destroy(g->ctx);
	free(g);
}

static void gles_describe(const void *impl, char *out, size_t cap)
{
	const struct gles *g = impl;
	snprintf(out, cap, "%s", g->renderer);
}

/* Compute kernels (RS_KERNELS_COMPUTE): GLES 3.1, or desktop GL running ES 3.1 shaders,
 * with the entry points, 4 image units (the fused pass's four outputs) and the kernels'
 * texture units in the compute stage. A function pointer alone proves nothing: EGL may hand
 * one out for any name. */
static void probe_compute(struct gles *g, const char *version, bool es31_compat)
{
	const struct rs_gl *gl = &g->gl;
	int major = 0, minor = 0;
	sscanf(g->es ? version + 9 : version, " %d.%d", &major, &minor);
	bool es31 = g->es ? major > 3 || (major == 3 && minor >= 1) : es31_compat;
	g->compute_glsl = NULL;
	/* test builds only (gles_seams.h): a context without compute */
	if (rs__gles_no_compute && rs__gles_no_compute())
		return;
	if (!es31 || !gl->DispatchCompute)
		return;
	GLint images = 0, units = 0;
	gl->GetIntegerv(GL_MAX_COMPUTE_IMAGE_UNIFORMS, &images);
	gl->GetIntegerv(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, &units);
	while (gl->GetError() != GL_NO_ERROR) {
	}
	if (images >= 4 && units >= UNIT_COUNT)
		g->compute_glsl = "#version 310 es\n";
}

static enum rs_status probe(struct gles *g, struct rs_error *err)
{
	const struct rs_gl *gl = &g->gl;
	const char *version = (const char *)gl->GetString(GL_VERSION);
	const char *renderer = (const char *)gl->GetString(GL_RENDERER);
	if (!version)
		return rs_error_set(err, RS_ERR_DEVICE, "gles: the context answers no GL_VERSION");
	int major = 0;
	g->es = strncmp(version, "OpenGL ES", 9) == 0;
	sscanf(g->es ? version + 9 : version, " %d", &major);
	if (major < 3)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: need GLES 3.0 or desktop GL 3.3, the context is \"%s\"",
		                    version);
	bool float_targets = !g->es, es3_compat = g->es, es31_compat = false;
	GLint n = 0;
	gl->GetIntegerv(GL_NUM_EXTENSIONS, &n);
	for (GLint i = 0; i < n; ++i) {
		const char *e = (const char *)gl->GetStringi(GL_EXTENSIONS, (GLuint)i);
		if (e && strcmp(e, "GL_EXT_color_buffer_float") == 0)
			float_targets = true;
		if (e && strcmp(e, "GL_ARB_ES3_compatibility") == 0)
			es3_compat = true;
		if (e && strcmp(e, "GL_ARB_ES3_1_compatibility") == 0)
			es31_compat = true;
	}
	rs_gles_probe_buffers(g, version);
	probe_compute(g, version, es31_compat);
	GLint dims[2] = {0, 0};
	gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &g->max_tex);
	gl->GetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
	gl->GetIntegerv(GL_MAX_DRAW_BUFFERS, &g->max_draw);
	g->max_view = dims[0] < dims[1] ? dims[0] : dims[1];
	if (g->max_draw < 4)
		return rs_error_set(err, RS_ERR_UNSUPPORTED, "gles: %d draw buffers (need 4)",
		                    (int)g->max_draw);
	if (!float_targets)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: %s cannot render to float textures "
		                    "(no EXT_color_buffer_float)",
		                    renderer ? renderer : "this GL");
	if (!es3_compat)
		return rs_error_set(err, RS_ERR_UNSUPPORTED,
		                    "gles: desktop GL without ARB_ES3_compatibility cannot run "
		                    "the #version 300 es kernels");
	char platform[48];
	g->cops->describe(g->ctx, platform, sizeof platform);
	snprintf(g->renderer, sizeof g->renderer, "%s (%s; %s)", renderer ? renderer : "?", version,
	         platform);
	/* RS_GLES_MAX_TEXTURE_SIZE lowers the limit, e.g. to GLES 3.0's guaranteed 2048, to
	 * check on a big desktop GL that a scene fits small devices. */
	const char *cap = getenv("RS_GLES_MAX_TEXTURE_SIZE");
	if (cap && atoi(cap) > 0 && atoi(cap) < g->max_tex)
		g->max_tex = atoi(cap);
	enum rs_status st = rs_gles_check(gl, "probing the context", err);
	if (st != RS_OK)
		return st;
	gl->GenVertexArrays(1, &g->vao);
	st = rs_gles_allocated(gl, "the vertex array object", 0, 0, 0, 0, err);
	if (st == RS_OK) {
		gl->GenFramebuffers(1, &g->fbo);
		st = rs_gles_allocated(gl, "the framebuffer object", 0, 0, 0, 0, err);
	}
	return st;
}

static const struct rs_renderer_ops gles_ops_egl = {.name = "egl",
                                                    .set_scene = gles_set_scene,
                                                    .render = gles_render,
                                                    .destroy = gles_destroy,
                                                    .describe = gles_describe,
                                                    .update_vertices = gles_update_vertices,
                                                    .update_instances = gles_update_instances};
static const struct rs_renderer_ops gles_ops_osmesa = {.name = "osmesa",
                                                       .set_scene = gles_set_scene,
                                                       .render = gles_render,
                                                       .destroy = gles_destroy,
                                                       .describe = gles_describe,
                                                       .update_vertices = gles_update_vertices,
                                                       .update_instances = gles_update_instances};

enum rs_status rs_gles_renderer_create(const struct rs_gl_context_ops *ops, void *ctx,
                                       const struct rs_render_desc *desc, struct rs_renderer **out,
                                       struct rs_error *err)
{
	RS_ASSERT(ops && out);
	*out = NULL;
	struct gles *g = calloc(1, sizeof *g);
	if (!g) {
		ops->destroy(ctx);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "gles: out of memory");
	}
	g->cops = ops;
	g->ctx = ctx;
	enum rs_status st = ops->make_current(ctx, err);
	if (st == RS_OK) {
		st = rs_gl_load(&g->gl, ops->get_proc_address, ctx, err);
		if (st == RS_OK)
			st = probe(g, err);
		ops->release(ctx);
	}
	if (st != RS_OK) {
		gles_destroy(g);
		return st;
	}
	const struct rs_renderer_ops *table =
	    strcmp(ops->backend, "osmesa") == 0 ? &gles_ops_osmesa : &gles_ops_egl;
	return rs_renderer_create(table, g, desc, out, err);
}
