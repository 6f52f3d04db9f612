// video: and cam: tracker sources: two frame streams (rs_optical_frames) through
// rs_optical_tracker into marker samples.
#include "optical_internal.hpp"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <vector>

using namespace rs_optical;

namespace
{

struct OpticalSource;

// The optical sources alive, for rs_optical_source_quality(): a track source keeps its
// implementation private, so the sources made here are looked up by their handle.
std::mutex g_lock;
std::vector<std::pair<const rs_track_source *, OpticalSource *>> g_sources;

struct OpticalSource {
	rs_optical_frames *frames[2] = {nullptr, nullptr};
	rs_optical_tracker *tracker = nullptr;
	bool live = false; // cam: host clock; video: frame index / rate
	double rate_hz = 60.0;
	uint32_t sequence = 0;
	rs_optical_quality quality{}; // of the last frame pair
	bool have_quality = false;
	~OpticalSource()
	{
		{
			std::lock_guard<std::mutex> lock(g_lock);
			g_sources.erase(
			    std::remove_if(g_sources.begin(), g_sources.end(),
			                   [this](const auto &e) { return e.second == this; }),
			    g_sources.end());
		}
		rs_optical_tracker_destroy(&tracker);
		rs_optical_frames_destroy(&frames[0]);
		rs_optical_frames_destroy(&frames[1]);
	}
};

// The key=value options after '?': calib (required), layout, rate, sigma_px.
struct Options {
	std::string a, b, calib, layout;
	double rate_hz = 60.0;
	double sigma_px = 0.0; // centroid noise the gate and the stated errors use (0: default)
	rs_optical_mask mask[2] = {};
	std::string mask_file[2]; // mask0file, mask1file: mask images
};

// mask0=X,Y,W,H[+X,Y,W,H...]: one camera's rectangles to ignore.
bool parse_mask(const std::string &v, rs_optical_mask *m)
{
	*m = rs_optical_mask{};
	size_t pos = 0;
	while (pos <= v.size()) {
		size_t plus = v.find('+', pos);
		std::string r =
		    v.substr(pos, plus == std::string::npos ? std::string::npos : plus - pos);
		long x, y, w, h;
		int used = 0;
		if (m->count >= RS_OPTICAL_MAX_MASK_RECTS ||
		    std::sscanf(r.c_str(), "%ld,%ld,%ld,%ld%n", &x, &y, &w, &h, &used) != 4 ||
		    used != (int)r.size() || w <= 0 || h <= 0 || w > 16384 || h > 16384 ||
		    x < -16384 || x > 16384 || y < -16384 || y > 16384)
			return false;
		m->rects[m->count++] = {(int32_t)x, (int32_t)y, (int32_t)w, (int32_t)h};
		if (plus == std::string::npos)
			return true;
		pos = plus + 1;
	}
	return false;
}

// mask<v>file=PATH: a grey image (PGM, PNG, anything OpenCV reads) of camera v's frame size
// whose nonzero pixels are masked, into `m` (pointing into `img`, which the caller keeps
// until the tracker has copied it).
rs_status load_mask_image(const std::string &path, int v, const rs_optical_camera &c, cv::Mat *img,
                          rs_optical_mask *m, rs_error *err)
{
	FILE *f = std::fopen(path.c_str(), "rb");
	if (!f)
		return rs_error_set(err, RS_ERR_NOT_FOUND,
		                    "optical: mask%dfile '%.200s': cannot open", v, path.c_str());
	std::fclose(f);
	try {
		*img = cv::imread(path, cv::IMREAD_GRAYSCALE);
	} catch (const cv::Exception &) {
		img->release();
	}
	if (img->empty())
		return rs_error_set(
		    err, RS_ERR_BAD_DATA,
		    "optical: mask%dfile '%.200s' is not an image OpenCV reads (PGM, "
		    "PNG)",
		    v, path.c_str());
	if (img->cols != c.width || img->rows != c.height)
		return rs_error_set(
		    err, RS_ERR_BAD_DATA,
		    "optical: mask%dfile '%.200s' is %dx%d, camera %d's frames %dx%d", v,
		    path.c_str(), img->cols, img->rows, v, c.width, c.height);
	m->pixels = img->data;
	m->width = img->cols;
	m->height = img->rows;
	m->stride = img->step[0];
	return RS_OK;
}

rs_status parse(const char *scheme, const char *rest, Options *o, rs_error *err)
{
	std::string r(rest);
	size_t qm = r.find('?');
	std::string streams = r.substr(0, qm);
	size_t comma = streams.find(',');
	if (comma == std::string::npos || comma == 0 || comma + 1 == streams.size())
		return rs_error_set(err, RS_ERR_PARSE, "%s: expected %s:LEFT,RIGHT?calib=FILE",
		                    scheme, scheme);
	o->a = streams.substr(0, comma);
	o->b = streams.substr(comma + 1);
	std::string q = qm == std::string::npos ? "" : r.substr(qm + 1);
	size_t pos = 0;
	while (qm != std::string::npos && pos <= q.size()) {
		size_t amp = q.find('&', pos);
		std::string kv =
		    q.substr(pos, amp == std::string::npos ? std::string::npos : amp - pos);
		size_t eq = kv.find('=');
		std::string k = kv.substr(0, eq),
		            v = eq == std::string::npos ? "" : kv.substr(eq + 1);
		if (eq == std::string::npos || v.empty())
			return rs_error_set(err, RS_ERR_PARSE, "%s: bad option '%.40s'", scheme,
			                    kv.c_str());
		if (k == "calib") {
			o->calib = v;
		} else if (k == "layout") {
			o->layout = v;
		} else if (k == "rate") {
			char *end = nullptr;
			o->rate_hz = std::strtod(v.c_str(), &end);
			if (*end || !(o->rate_hz >= 0.01 && o->rate_hz <= 1e6))
				return rs_error_set(err, RS_ERR_PARSE, "%s: bad rate '%.40s'",
				                    scheme, v.c_str());
		} else if (k == "sigma_px") {
			char *end = nullptr;
			o->sigma_px = std::strtod(v.c_str(), &end);
			if (*end || !(o->sigma_px >= 1e-4 && o->sigma_px <= 100))
				return rs_error_set(err, RS_ERR_PARSE, "%s: bad sigma_px '%.40s'",
				                    scheme, v.c_str());
		} else if (k == "mask0file" || k == "mask1file") {
			o->mask_file[k[4] - '0'] = v;
		} else if (k == "mask0" || k == "mask1") {
			if (!parse_mask(v, &o->mask[k[4] - '0']))
				return rs_error_set(
				    err, RS_ERR_PARSE,
				    "%s: bad %s '%.40s' (X,Y,W,H[+X,Y,W,H], at most %d)", scheme,
				    k.c_str(), v.c_str(), RS_OPTICAL_MAX_MASK_RECTS);
		} else {
			return rs_error_set(err, RS_ERR_PARSE,
			                    "%s: unknown option '%.40s' (calib, layout, rate, "
			                    "sigma_px, mask0, mask1, mask0file, mask1file)",
			                    scheme, k.c_str());
		}
		if (amp == std::string::npos)
			break;
		pos = amp + 1;
	}
	if (o->calib.empty())
		return rs_error_set(err, RS_ERR_PARSE, "%s: needs ?calib=FILE (raystream-calib)",
		                    scheme);
	return RS_OK;
}

rs_status src_read(void *impl, rs_marker_sample *out, int timeout_ms, rs_error *err)
{
	OpticalSource *s = static_cast<OpticalSource *>(impl);
	(void)timeout_ms; // a frame read blocks for at most one frame interval
	rs_optical_image img[2];
	for (int v = 0; v < 2; ++v) {
		rs_status st = rs_optical_frames_read(s->frames[v], &img[v], err);
		if (st != RS_OK) {
			// Say which stream ended or failed; keep the status.
			std::string m = err ? err->message : "";
			return rs_error_set(err, st, "%s (stream %d, frame %u)", m.c_str(), v,
			                    s->sequence);
		}
	}
	double t = s->live ? rs_track_now_s() : s->sequence / s->rate_hz;
	rs_optical_quality q;
	rs_status st = rs_optical_tracker_process(s->tracker, &img[0], &img[1], t, out, &q, err);
	if (st != RS_OK)
		return st;
	{
		std::lock_guard<std::mutex> lock(g_lock);
		s->quality = q;
		s->have_quality = true;
	}
	out->sequence = s->sequence;
	out->device_time_us = (uint64_t)std::llround(t * 1e6);
	s->sequence++;
	return RS_OK;
}

void src_destroy(void *impl)
{
	delete static_cast<OpticalSource *>(impl);
}

const rs_track_source_ops k_ops = {src_read, nullptr, nullptr, src_destroy};

} // namespace

extern "C" enum rs_status rs_optical_open_uri(const char *scheme, const char *rest,
                                              struct rs_track_source **out, struct rs_error *err)
{
	RS_ASSERT(scheme && rest && out);
	*out = nullptr;
	bool camera = !std::strcmp(scheme, "cam");
	if (!camera && std::strcmp(scheme, "video"))
		return rs_error_set(err, RS_ERR_PARSE, "optical: unknown scheme '%.20s'", scheme);
	Options o;
	rs_status st = parse(scheme, rest, &o, err);
	if (st != RS_OK)
		return st;
	rs_optical_tracker_desc d{};
	d.centroid_sigma_px = o.sigma_px;
	d.mask[0] = o.mask[0];
	d.mask[1] = o.mask[1];
	if ((st = rs_optical_rig_load(o.calib.c_str(), &d.rig, err)) != RS_OK)
		return st;
	if (!o.layout.empty() &&
	    (st = rs_pose_layout_load(o.layout.c_str(), &d.layout, err)) != RS_OK)
		return st;
	cv::Mat mask_img[2];
	for (int v = 0; v < 2; ++v)
		if (!o.mask_file[v].empty() &&
		    (st = load_mask_image(o.mask_file[v], v, d.rig.cam[v], &mask_img[v], &d.mask[v],
		                          err)) != RS_OK)
			return st;
	OpticalSource *s = new (std::nothrow) OpticalSource();
	if (!s)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "optical: out of memory");
	s->live = camera;
	s->rate_hz = o.rate_hz;
	if ((st = rs_optical_tracker_create(&d, &s->tracker, err)) != RS_OK) {
		delete s;
		return st;
	}
	const std::string *names[2] = {&o.a, &o.b};
	for (int v = 0; v < 2; ++v)
		if ((st = rs_optical_frames_open(names[v]->c_str(), camera, &s->frames[v], err)) !=
		    RS_OK) {
			delete s;
			return st;
		}
	if ((st = rs_track_source_create(&k_ops, s, out, err)) != RS_OK)
		return st; // k_ops.destroy freed s
	try {
		std::lock_guard<std::mutex> lock(g_lock);
		g_sources.emplace_back(*out, s);
	} catch (const std::bad_alloc &) {
		rs_track_source_destroy(out);
		return rs_error_set(err, RS_ERR_NO_MEMORY, "optical: out of memory");
	}
	return RS_OK;
}

extern "C" bool rs_optical_source_quality(const struct rs_track_source *src,
                                          struct rs_optical_quality *out)
{
	RS_ASSERT(out);
	std::lock_guard<std::mutex> lock(g_lock);
	for (const auto &e : g_sources)
		if (e.first == src && e.second->have_quality) {
			*out = e.second->quality;
			return true;
		}
	return false;
}
