/* The #define prelude every kernel program is compiled under, written from one table: the
 * scene's specialisation (which code the kernels keep) and the rule constants of the frame
 * description (rs_trace_frame.rules, docs/tracer.md R2-R5), so no number is typed once in
 * C and again in GLSL. Every define is always written (0 or 1 for a switch, tested with
 * #if), and a prelude that would not fit is an error, never cut short. */
#include <stdio.h>
#include <string.h>

#include "gles_internal.h"

/* A GLSL float literal of `v` rounded to fp32: 9 significant digits give the same float
 * back; a '.' is added where %g writes none (GLSL ES has no implicit int -> float). */
static void float_literal(double v, char *out, size_t cap)
{
	char digits[32];
	snprintf(digits, sizeof digits, "%.9g", (double)(float)v);
	bool has_point = strpbrk(digits, ".e") != NULL;
	snprintf(out, cap, "(%s%s)", digits, has_point ? "" : ".0");
}

enum rs_status rs_gles_prelude(const struct rs_gles_spec *spec, const struct rs_trace_rules *rules,
                               char *out, size_t cap, struct rs_error *err)
{
	RS_ASSERT(spec && rules && out && cap > 0);
	const struct {
		const char *name;
		bool is_float;
		double value;
	} table[] = {
	    /* the scene's specialisation */
	    {"RS_ROW_ITEMS", false, spec->row_items},
	    {"RS_ROW_SHIFT", false, spec->row_shift},
	    {"RS_WATERTIGHT", false, spec->watertight},
	    {"RS_LIGHTS", false, spec->lights},
	    /* an array of 0 lights is not GLSL: loop over RS_LIGHTS, size arrays at least 1 */
	    {"RS_LIGHT_SLOTS", false, spec->lights ? spec->lights : 1u},
	    {"RS_COUNTERS", false, spec->counters},
	    {"RS_OPTICS", false, spec->optics},
	    {"RS_GEOMETRY", false, spec->geometry},
	    {"RS_SHADOW_MAP", false, spec->shadow_map},
	    {"RS_SHADOW_NONE", false, spec->unshadowed},
	    {"RS_ENVMAP", false, spec->envmap},
	    {"RS_INTERREFLECT", false, spec->interreflect},
	    {"RS_COMPACT_NODES", false, spec->compact_nodes},
	    {"RS_WIDE_NODES", false, spec->wide_nodes},
	    {"RS_WIDE_STACK", false, RS_PACK_WIDE_STACK},
	    {"RS_NODE_ORDERS", false, spec->node_orders},
	    {"RS_SCENE_BUFFERS", false, spec->scene_buffers},
	    {"RS_TWO_LEVEL", false, spec->two_level},
	    {"RS_INSTANCE_TEXELS", false, RS_PACK_INSTANCE_TEXELS},
	    {"RS_INSTANCE_ROW_ITEMS", false,
	     spec->instance_row_items ? spec->instance_row_items : 1u},
	    {"RS_FIRST_PASS", false, spec->first_pass},
	    {"RS_RASTER_FIRST", false, spec->raster_first},
	    /* the rules (docs/tracer.md), in fp32 */
	    {"RS_BOX_K", true, rules->box_k_fp32},
	    {"RS_GRID_BOX_E", true, rules->grid_box_e_fp32},
	    {"RS_GRID_STEPS", true, RS_PACK_GRID_STEPS},
	    {"RS_PARALLEL_EPS", true, rules->parallel_eps},
	    {"RS_SPAWN_PULL_HEIGHT", true, rules->spawn_pull_height},
	    {"RS_SPAWN_PULL", true, rules->spawn_pull},
	    /* material flags (rs_scene.h) */
	    {"RS_FRESNEL", false, RS_MATERIAL_FRESNEL},
	    /* the paper's ray states (enum rs_ray_state) */
	    {"RS_STATE_ACTIVE", true, RS_RAY_ACTIVE},
	    {"RS_STATE_MISSED", true, RS_RAY_MISSED},
	    {"RS_STATE_ENVIRONMENT", true, RS_RAY_ENVIRONMENT},
	    {"RS_STATE_DIFFUSE", true, RS_RAY_DIFFUSE},
	};
	size_t len = 0;
	for (size_t i = 0; i < sizeof table / sizeof table[0]; ++i) {
		char value[48];
		if (table[i].is_float)
			float_literal(table[i].value, value, sizeof value);
		else
			snprintf(value, sizeof value, "%lld", (long long)table[i].value);
		int n = snprintf(out + len, cap - len, "#define %s %s\n", table[i].name, value);
		if (n < 0 || (size_t)n >= cap - len) {
			out[len] = '\0';
			return rs_error_set(err, RS_ERR_LIMIT,
			                    "gles: the kernels' #define prelude is over %zu bytes",
			                    cap);
		}
		len += (size_t)n;
	}
	return RS_OK;
}
