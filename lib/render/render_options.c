/* Render options as text: one table of keys, their values and defaults, and the one parser
 * every command line and config string goes through ("passes=2,lights=4"), so a tool, an
 * app and a library caller spell and check an option the same way. */
#include <stdio.h>
#include <string.h>

#include "private/rs_parse.h"
#include "raystream/rs_render.h"

#define MAX_LIGHTS 64u

static const struct rs_render_option options[] = {
    {"backend", "auto|cpu|egl|osmesa", "auto",
     "auto: egl, else osmesa where a GL context opens, else cpu"},
    {"size", "WxH", "camera", "image size, sides 1..16384; camera: the scene camera's"},
    {"passes", "1..64", "2", "ray segments per path"},
    {"lights", "1..64|all", "all", "use the scene's first N lights"},
    {"shadows", "rays|map[:RES[:FILTER]]|none", "rays",
     "feelers, cube maps (GL): RES 8..16384 [512], FILTER 1..64 [3]; none: all lit"},
    {"primary", "trace|raster", "trace", "primary hits traced or rasterized (GL)"},
    {"reflections", "trace|envmap|interreflect[:1..8]", "trace",
     "traced, or environment maps (GL)"},
    {"envmap-size", "8..16384", "128", "environment map cube face side in texels (GL)"},
    {"bvh", "sah|none|linear|paper", "sah", "BVH builder (docs/bvh.md)"},
    {"nodes", "compact|paper[:directional|octant|single]|wide4", "compact:directional",
     "node texels:orders; paper:single is the paper's; wide4: 4-wide quantised"},
    {"scene-storage", "auto|2d|buffer", "auto", "GL: buffer textures where the context has them"},
    {"threads", "1..256", "cores", "CPU backend and BVH build threads; cores: the machine's"},
    {"triangle-test", "watertight|mt", "watertight", "mt: the paper's Moller-Trumbore"},
    {"chain", "fused|separate|paper", "fused", "GL: how kernels are chained"},
    {"kernels", "fragment|compute", "fragment",
     "GL: the fused chain as fragment passes, or GLES 3.1 compute dispatches"},
    {"instances", "auto|flatten|two-level", "auto",
     "instanced scenes: BLAS per mesh + TLAS, or flattened (auto: CPU two levels; GL "
     "flattened until instances move or where it does not fit)"},
};

#define COUNT (sizeof options / sizeof options[0])

const struct rs_render_option *rs_render_options(size_t *out_count)
{
	RS_ASSERT(out_count);
	*out_count = COUNT;
	return options;
}

const struct rs_render_option *rs_render_option_find(const char *key)
{
	for (size_t i = 0; key && i < COUNT; ++i)
		if (strcmp(options[i].key, key) == 0)
			return &options[i];
	return NULL;
}

/* The index of `value` in names[0..n), or -1. */
static int pick(const char *value, const char *const *names, int n)
{
	for (int i = 0; i < n; ++i)
		if (strcmp(value, names[i]) == 0)
			return i;
	return -1;
}

static const char *const backends[] = {"auto", "cpu", "egl", "osmesa"};
static const char *const primaries[] = {"trace", "raster"};
static const char *const instance_modes[] = {"auto", "flatten", "two-level"};
static const char *const storages[] = {"auto", "2d", "buffer"};
static const char *const tests[] = {"watertight", "mt"};
static const char *const chains[] = {"fused", "separate", "paper"};
static const char *const stages[] = {"fragment", "compute"};

/* "rays", "none", "map", "map:RES" or "map:RES:FILTER". */
static bool set_shadows(struct rs_render_desc *d, const char *v)
{
	bool none = strcmp(v, "none") == 0;
	if (none || strcmp(v, "rays") == 0) {
		d->shadows = none ? RS_SHADOW_NONE : RS_SHADOW_RAYS;
		d->shadow_map_size = d->shadow_filter = 0;
		return true;
	}
	if (strncmp(v, "map", 3) != 0 || (v[3] != '\0' && v[3] != ':'))
		return false;
	uint32_t size = 0, filter = 0;
	if (v[3] == ':') {
		char res[16];
		const char *colon = strchr(v + 4, ':');
		size_t n = colon ? (size_t)(colon - (v + 4)) : strlen(v + 4);
		if (n == 0 || n >= sizeof res)
			return false;
		memcpy(res, v + 4, n);
		res[n] = '\0';
		if (!rs_parse_u32(res, 8, 16384, &size) ||
		    (colon && !rs_parse_u32(colon + 1, 1, 64, &filter)))
			return false;
	}
	d->shadows = RS_SHADOW_MAP;
	d->shadow_map_size = size;
	d->shadow_filter = filter;
	return true;
}

static bool set_reflections(struct rs_render_desc *d, const char *v)
{
	uint32_t bounces = 0;
	if (strcmp(v, "trace") == 0)
		d->reflections = RS_REFLECT_TRACE;
	else if (strcmp(v, "envmap") == 0)
		d->reflections = RS_REFLECT_ENVMAP;
	else if (strcmp(v, "interreflect") == 0 ||
	         (strncmp(v, "interreflect:", 13) == 0 &&
	          rs_parse_u32(v + 13, 1, RS_RENDER_MAX_BOUNCES, &bounces)))
		d->reflections = RS_REFLECT_INTERREFLECT;
	else
		return false;
	d->reflection_bounces = bounces;
	return true;
}

static bool set_nodes(struct rs_render_desc *d, const char *v)
{
	const char *colon = strchr(v, ':');
	size_t n = colon ? (size_t)(colon - v) : strlen(v);
	enum rs_pack_nodes nodes;
	enum rs_pack_orders orders = RS_PACK_ORDERS_DIRECTIONAL;
	if (n == 7 && strncmp(v, "compact", n) == 0)
		nodes = RS_PACK_NODES_COMPACT;
	else if (n == 5 && strncmp(v, "paper", n) == 0)
		nodes = RS_PACK_NODES_PAPER;
	else if (n == 5 && strncmp(v, "wide4", n) == 0 && !colon)
		nodes = RS_PACK_NODES_WIDE4; /* one order: children are ordered per ray */
	else
		return false;
	if (colon && strcmp(colon + 1, "single") == 0)
		orders = RS_PACK_ORDERS_SINGLE;
	else if (colon && strcmp(colon + 1, "octant") == 0)
		orders = RS_PACK_ORDERS_OCTANT;
	else if (colon && strcmp(colon + 1, "directional") != 0)
		return false;
	d->pack.nodes = nodes;
	d->pack.orders = orders;
	return true;
}

/* Parse `v` for `o` into `d`; false when it is not one of o->values. */
static bool set_value(struct rs_render_desc *d, const struct rs_render_option *o, const char *v)
{
	const char *k = o->key;
	int i;
#define PICK(names) ((i = pick(v, names, (int)(sizeof names / sizeof names[0]))) >= 0)
	if (!strcmp(k, "backend") && PICK(backends))
		d->backend = backends[i];
	else if (!strcmp(k, "size"))
		return rs_parse_size(v, 16384, &d->width, &d->height);
	else if (!strcmp(k, "passes"))
		return rs_parse_u32(v, 1, RS_TRACE_MAX_PASSES, &d->passes);
	else if (!strcmp(k, "lights"))
		return !strcmp(v, "all") ? (d->lights = 0, true)
		                         : rs_parse_u32(v, 1, MAX_LIGHTS, &d->lights);
	else if (!strcmp(k, "shadows"))
		return set_shadows(d, v);
	else if (!strcmp(k, "primary") && PICK(primaries))
		d->primary = (enum rs_primary_mode)i;
	else if (!strcmp(k, "reflections"))
		return set_reflections(d, v);
	else if (!strcmp(k, "envmap-size"))
		return rs_parse_u32(v, 8, RS_RENDER_MAX_ENVMAP_SIZE, &d->envmap_size);
	else if (!strcmp(k, "bvh"))
		return rs_bvh_builder_parse(v, &d->bvh.builder, NULL) == RS_OK;
	else if (!strcmp(k, "nodes"))
		return set_nodes(d, v);
	else if (!strcmp(k, "scene-storage") && PICK(storages))
		d->scene_storage = (enum rs_scene_storage)i;
	else if (!strcmp(k, "threads"))
		return rs_parse_u32(v, 1, RS_RENDER_MAX_THREADS, &d->threads);
	else if (!strcmp(k, "triangle-test") && PICK(tests))
		d->triangle_test = i ? RS_TRIANGLE_MOLLER_TRUMBORE : RS_TRIANGLE_WATERTIGHT;
	else if (!strcmp(k, "chain") && PICK(chains))
		d->chain = (enum rs_kernel_chain)i;
	else if (!strcmp(k, "kernels") && PICK(stages))
		d->kernels = (enum rs_kernel_stage)i;
	else if (!strcmp(k, "instances") && PICK(instance_modes))
		d->instances = (enum rs_instances_mode)i;
	else
		return false;
#undef PICK
	return true;
}

enum rs_status rs_render_desc_set(struct rs_render_desc *desc, const char *key, const char *value,
                                  struct rs_error *err)
{
	RS_ASSERT(desc && key && value);
	const struct rs_render_option *o = rs_render_option_find(key);
	if (!o)
		return rs_error_set(err, RS_ERR_INVALID,
		                    "unknown render option '%s' (backend, size, passes, lights, "
		                    "shadows, primary, reflections, envmap-size, bvh, nodes, "
		                    "scene-storage, "
		                    "threads, triangle-test, chain, kernels, instances)",
		                    key);
	/* A failed parse leaves the descriptor as it was. */
	struct rs_render_desc d = *desc;
	if (!set_value(&d, o, value))
		return rs_error_set(err, RS_ERR_INVALID, "%s: '%s' is not %s", o->key, value,
		                    o->values);
	*desc = d;
	return RS_OK;
}

enum rs_status rs_render_desc_parse(struct rs_render_desc *desc, const char *config,
                                    struct rs_error *err)
{
	RS_ASSERT(desc && config);
	struct rs_render_desc d = *desc;
	char item[256];
	for (const char *p = config; *p;) {
		const char *end = strchr(p, ',');
		size_t n = end ? (size_t)(end - p) : strlen(p);
		if (n >= sizeof item)
			return rs_error_set(err, RS_ERR_INVALID,
			                    "render options: '%.40s...' is too long", p);
		memcpy(item, p, n);
		item[n] = '\0';
		char *eq = strchr(item, '=');
		if (!eq || eq == item)
			return rs_error_set(err, RS_ERR_INVALID,
			                    "render options: '%s' is not key=value", item);
		*eq = '\0';
		enum rs_status st = rs_render_desc_set(&d, item, eq + 1, err);
		if (st != RS_OK)
			return st;
		p = end ? end + 1 : p + n;
	}
	*desc = d;
	return RS_OK;
}

enum rs_status rs_render_desc_get(const struct rs_render_desc *desc, const char *key, char *out,
                                  size_t cap, struct rs_error *err)
{
	RS_ASSERT(desc && key && out && cap > 0);
	const struct rs_render_option *o = rs_render_option_find(key);
	if (!o)
		return rs_error_set(err, RS_ERR_INVALID, "unknown render option '%s'", key);
	const struct rs_render_desc *d = desc;
	int n;
	if (!strcmp(key, "backend"))
		n = snprintf(out, cap, "%s", d->backend ? d->backend : o->fallback);
	else if (!strcmp(key, "size"))
		n = d->width ? snprintf(out, cap, "%ux%u", d->width, d->height)
		             : snprintf(out, cap, "%s", o->fallback);
	else if (!strcmp(key, "passes"))
		n = snprintf(out, cap, "%u", d->passes ? d->passes : 2u);
	else if (!strcmp(key, "lights"))
		n = d->lights ? snprintf(out, cap, "%u", d->lights) : snprintf(out, cap, "all");
	else if (!strcmp(key, "shadows"))
		n = d->shadows != RS_SHADOW_MAP
		        ? snprintf(out, cap, "%s", d->shadows == RS_SHADOW_NONE ? "none" : "rays")
		        : snprintf(out, cap, "map:%u:%u",
		                   d->shadow_map_size ? d->shadow_map_size : 512u,
		                   d->shadow_filter ? d->shadow_filter : 3u);
	else if (!strcmp(key, "primary"))
		n = snprintf(out, cap, "%s", d->primary == RS_PRIMARY_RASTER ? "raster" : "trace");
	else if (!strcmp(key, "reflections"))
		n = d->reflections == RS_REFLECT_INTERREFLECT
		        ? snprintf(out, cap, "interreflect:%u",
		                   d->reflection_bounces ? d->reflection_bounces : 1u)
		        : snprintf(out, cap, "%s",
		                   d->reflections == RS_REFLECT_ENVMAP ? "envmap" : "trace");
	else if (!strcmp(key, "envmap-size"))
		n = snprintf(out, cap, "%u",
		             d->envmap_size ? d->envmap_size : RS_RENDER_ENVMAP_SIZE);
	else if (!strcmp(key, "bvh"))
		n = snprintf(out, cap, "%s", rs_bvh_builder_name(d->bvh.builder));
	else if (!strcmp(key, "nodes") && d->pack.nodes == RS_PACK_NODES_WIDE4)
		n = snprintf(out, cap, "wide4");
	else if (!strcmp(key, "nodes"))
		n = snprintf(out, cap, "%s:%s",
		             d->pack.nodes == RS_PACK_NODES_PAPER ? "paper" : "compact",
		             d->pack.orders == RS_PACK_ORDERS_SINGLE   ? "single"
		             : d->pack.orders == RS_PACK_ORDERS_OCTANT ? "octant"
		                                                       : "directional");
	else if (!strcmp(key, "scene-storage"))
		n = snprintf(out, cap, "%s",
		             (unsigned)d->scene_storage < 3 ? storages[d->scene_storage] : "?");
	else if (!strcmp(key, "threads"))
		n = d->threads ? snprintf(out, cap, "%u", d->threads) : snprintf(out, cap, "cores");
	else if (!strcmp(key, "triangle-test"))
		n = snprintf(out, cap, "%s",
		             d->triangle_test == RS_TRIANGLE_MOLLER_TRUMBORE ? "mt" : "watertight");
	else if (!strcmp(key, "kernels"))
		n = snprintf(out, cap, "%s", (unsigned)d->kernels < 2 ? stages[d->kernels] : "?");
	else if (!strcmp(key, "instances"))
		n = snprintf(out, cap, "%s",
		             (unsigned)d->instances < 3 ? instance_modes[d->instances] : "?");
	else
		n = snprintf(out, cap, "%s", (unsigned)d->chain < 3 ? chains[d->chain] : "?");
	if (n < 0 || (size_t)n >= cap)
		return rs_error_set(err, RS_ERR_LIMIT, "render option %s: %zu bytes are too few",
		                    key, cap);
	return RS_OK;
}
