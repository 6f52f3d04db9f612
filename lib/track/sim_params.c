/*
 * "sim:" URI parameters: key=value pairs joined by '&', numbers with optional units.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "raystream/rs_track.h"

/* Parse `v` as a finite number followed by one of `units` (a suffix and its scale);
 * an empty suffix uses scale 1. */
struct unit {
	const char *suffix;
	double scale;
};

static const struct unit length_units[] = {{"mm", 1e-3}, {"um", 1e-6}, {"m", 1.0}, {NULL, 0}};
static const struct unit time_units[] = {{"ms", 1e-3}, {"us", 1e-6}, {"s", 1.0}, {NULL, 0}};
static const struct unit rate_units[] = {{"hz", 1.0}, {"Hz", 1.0}, {NULL, 0}};
static const struct unit no_units[] = {{NULL, 0}};

static int parse_number(const char *v, size_t n, const struct unit *units, double *out)
{
	char buf[64];
	if (n == 0 || n >= sizeof buf)
		return 0;
	memcpy(buf, v, n);
	buf[n] = '\0';
	char *end = NULL;
	double x = strtod(buf, &end);
	if (end == buf || !isfinite(x))
		return 0;
	double scale = 1.0;
	if (*end) {
		const struct unit *u = units;
		while (u->suffix && strcmp(u->suffix, end) != 0)
			u++;
		if (!u->suffix)
			return 0;
		scale = u->scale;
	}
	*out = x * scale;
	return 1;
}

static int parse_uint(const char *v, size_t n, uint64_t max, uint64_t *out)
{
	if (n == 0 || n > 20)
		return 0;
	uint64_t x = 0;
	for (size_t i = 0; i < n; i++) {
		if (v[i] < '0' || v[i] > '9')
			return 0;
		unsigned d = (unsigned)(v[i] - '0');
		if (x > (max - d) / 10)
			return 0;
		x = x * 10 + d;
	}
	*out = x;
	return 1;
}

static int key_is(const char *key, size_t n, const char *name)
{
	return strlen(name) == n && !strncmp(key, name, n);
}

enum rs_status rs_sim_parse_pair(const char *key, size_t kn, const char *v, size_t vn,
                                 struct rs_sim_desc *d, char *script_buf, size_t script_cap,
                                 struct rs_error *err)
{
	struct {
		const char *name;
		const struct unit *units;
		double *dst;
	} nums[] = {
	    {"rate", rate_units, &d->rate_hz},
	    {"noise", length_units, &d->noise_sigma_m},
	    {"dropout", no_units, &d->dropout_prob},
	    {"occlusion", no_units, &d->occlusion_prob},
	    {"occlusion_time", time_units, &d->occlusion_s},
	    {"swap", no_units, &d->swap_prob},
	    {"jitter", time_units, &d->clock_jitter_s},
	    {"duration", time_units, &d->duration_s},
	};
	for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++) {
		if (!key_is(key, kn, nums[i].name))
			continue;
		if (!parse_number(v, vn, nums[i].units, nums[i].dst) || *nums[i].dst < 0)
			return rs_error_set(err, RS_ERR_PARSE, "sim: bad value '%.*s' for %s",
			                    (int)(vn > 40 ? 40 : vn), v, nums[i].name);
		/* In the descriptor 0 means "default 120 Hz"; written out, rate=0 is a
		 * mistake, not a request for the default. */
		if (nums[i].dst == &d->rate_hz && !(d->rate_hz >= 0.01 && d->rate_hz <= 1e6))
			return rs_error_set(err, RS_ERR_PARSE,
			                    "sim: rate '%.*s' out of range [0.01, 1e6] Hz",
			                    (int)(vn > 40 ? 40 : vn), v);
		return RS_OK;
	}
	uint64_t u;
	if (key_is(key, kn, "seed") || key_is(key, kn, "first_seq")) {
		int seed = key_is(key, kn, "seed");
		if (!parse_uint(v, vn, seed ? UINT64_MAX : UINT32_MAX, &u))
			return rs_error_set(err, RS_ERR_PARSE, "sim: bad value '%.*s' for %.*s",
			                    (int)(vn > 40 ? 40 : vn), v, (int)kn, key);
		if (seed)
			d->seed = u;
		else
			d->first_sequence = (uint32_t)u;
		return RS_OK;
	}
	if (key_is(key, kn, "script")) {
		if (!script_buf || vn + 1 > script_cap)
			return rs_error_set(err, RS_ERR_PARSE, "sim: script too long");
		memcpy(script_buf, v, vn);
		script_buf[vn] = '\0';
		d->script = script_buf;
		return RS_OK;
	}
	return rs_error_set(err, RS_ERR_NOT_FOUND, "sim: unknown parameter '%.*s'",
	                    (int)(kn > 40 ? 40 : kn), key);
}

/* Split `params` at '&' and '='; calls pair() for each. */
static enum rs_status each_pair(const char *params, struct rs_track_sim_source_desc *sd,
                                struct rs_sim_desc *d, char *script_buf, size_t script_cap,
                                struct rs_error *err)
{
	const char *p = params ? params : "";
	while (*p) {
		size_t len = strcspn(p, "&");
		const char *eq = memchr(p, '=', len);
		if (len == 0) {
			p++;
			continue;
		}
		if (!eq || eq == p)
			return rs_error_set(err, RS_ERR_PARSE,
			                    "sim: expected key=value, got '%.*s'",
			                    (int)(len > 40 ? 40 : len), p);
		size_t kn = (size_t)(eq - p), vn = len - kn - 1;
		enum rs_status st =
		    rs_sim_parse_pair(p, kn, eq + 1, vn, d, script_buf, script_cap, err);
		if (st == RS_ERR_NOT_FOUND && sd && kn == 8 && !strncmp(p, "realtime", 8)) {
			if (vn != 1 || (eq[1] != '0' && eq[1] != '1'))
				return rs_error_set(err, RS_ERR_PARSE,
				                    "sim: realtime must be 0 or 1");
			sd->realtime = eq[1] == '1';
			st = RS_OK;
		}
		if (st == RS_ERR_NOT_FOUND)
			return rs_error_set(err, RS_ERR_PARSE, "sim: unknown parameter '%.*s'",
			                    (int)(kn > 40 ? 40 : kn), p);
		if (st != RS_OK)
			return st;
		p += len;
		if (*p == '&')
			p++;
	}
	return RS_OK;
}

enum rs_status rs_sim_parse_params(const char *params, struct rs_sim_desc *out_desc,
                                   char *script_buf, size_t script_cap, struct rs_error *err)
{
	RS_ASSERT(out_desc);
	memset(out_desc, 0, sizeof *out_desc);
	return each_pair(params, NULL, out_desc, script_buf, script_cap, err);
}

enum rs_status rs_track_sim_parse_params(const char *params,
                                         struct rs_track_sim_source_desc *out_desc,
                                         char *script_buf, size_t script_cap, struct rs_error *err)
{
	RS_ASSERT(out_desc);
	memset(out_desc, 0, sizeof *out_desc);
	return each_pair(params, out_desc, &out_desc->sim, script_buf, script_cap, err);
}
