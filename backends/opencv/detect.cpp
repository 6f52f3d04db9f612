// Marker blobs: threshold, connected components, intensity-weighted sub-pixel centroids,
// and the area and shape gates that drop noise, lamps, reflections and merged markers.
#include "optical_internal.hpp"
#include "optical_detect.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace rs_optical
{

void resolve_detect(const rs_optical_detect_desc *in, rs_optical_detect_desc *out)
{
	*out = in ? *in : rs_optical_detect_desc{};
	if (!out->threshold)
		out->threshold = 100;
	if (out->min_area_px == 0.0)
		out->min_area_px = 3.0;
	if (out->max_area_px == 0.0)
		out->max_area_px = 400.0;
	if (out->max_aspect == 0.0)
		out->max_aspect = 1.6;
}

bool detect_desc_valid(const rs_optical_detect_desc &d)
{
	return d.threshold > 0 && d.threshold < 255 && std::isfinite(d.min_area_px) &&
	       std::isfinite(d.max_area_px) && d.min_area_px > 0 &&
	       d.max_area_px >= d.min_area_px && std::isfinite(d.max_aspect) && d.max_aspect >= 1.0;
}

static bool window_has_other(const cv::Mat &labels, int i, int x0, int y0, int x1, int y1)
{
	for (int y = y0; y < y1; ++y) {
		const int *lab = labels.ptr<int>(y);
		for (int x = x0; x < x1; ++x)
			if (lab[x] != 0 && lab[x] != i)
				return true;
	}
	return false;
}

bool window_masked(const Mask *mask, int x0, int y0, int x1, int y1)
{
	if (!mask)
		return false;
	const rs_optical_mask *m = mask->rects;
	for (uint32_t k = 0; m && k < m->count && k < RS_OPTICAL_MAX_MASK_RECTS; ++k) {
		const rs_optical_rect &r = m->rects[k];
		if (x0 < (int64_t)r.x + r.width && r.x < x1 && y0 < (int64_t)r.y + r.height &&
		    r.y < y1)
			return true;
	}
	if (mask->sum.empty())
		return false;
	// The window clipped to the image: how many masked pixels it holds.
	int cx0 = std::max(x0, 0), cy0 = std::max(y0, 0);
	int cx1 = std::min(x1, mask->sum.cols - 1), cy1 = std::min(y1, mask->sum.rows - 1);
	if (cx0 >= cx1 || cy0 >= cy1)
		return false;
	const cv::Mat &S = mask->sum;
	return S.at<int>(cy1, cx1) - S.at<int>(cy0, cx1) - S.at<int>(cy1, cx0) +
	           S.at<int>(cy0, cx0) >
	       0;
}

void detect(const cv::Mat &img, const rs_optical_detect_desc &d, DetectScratch &s,
            std::vector<rs_optical_blob> &out, DetectCounts *counts, const Mask *mask)
{
	out.clear();
	if (counts)
		*counts = DetectCounts{};
	cv::threshold(img, s.binary, d.threshold, 255, cv::THRESH_BINARY);
	int n =
	    cv::connectedComponentsWithStats(s.binary, s.labels, s.stats, s.centroids, 8, CV_32S);
	for (int i = 1; i < n; ++i) {
		int area = s.stats.at<int>(i, cv::CC_STAT_AREA);
		if (area < d.min_area_px || area > d.max_area_px)
			continue;
		// The spot's flanks below the threshold belong to the centroid too, so the window
		// reaches 3 px beyond the thresholded pixels, and the weight is the brightness
		// above the local background (the window's rim): linear in how much of a pixel
		// the marker covers, so the centroid of a symmetric spot has no bias.
		const int m = k_centroid_margin_px;
		int x0 = s.stats.at<int>(i, cv::CC_STAT_LEFT) - m;
		int y0 = s.stats.at<int>(i, cv::CC_STAT_TOP) - m;
		int x1 = s.stats.at<int>(i, cv::CC_STAT_LEFT) +
		         s.stats.at<int>(i, cv::CC_STAT_WIDTH) + m;
		int y1 = s.stats.at<int>(i, cv::CC_STAT_TOP) +
		         s.stats.at<int>(i, cv::CC_STAT_HEIGHT) + m;
		// A window cut by the image edge loses one flank of the spot: its centroid moves
		// 0.2-0.6 px inwards (issue 19), a pose error many times the stated one. Such a
		// blob is not a measurement.
		if (x0 < 0 || y0 < 0 || x1 > img.cols || y1 > img.rows) {
			if (counts)
				counts->at_edge++;
			continue;
		}
		// A region the user masked (a lamp, a glossy surface the room always shows): its
		// light is not a marker's, and a marker next to it has a biased background.
		if (window_masked(mask, x0, y0, x1, y1)) {
			if (counts)
				counts->masked++;
			continue;
		}
		// Another bright region (a neighbouring spot, a lamp, a saturated reflection)
		// inside the window biases the background and the flanks alike.
		if (window_has_other(s.labels, i, x0, y0, x1, y1)) {
			if (counts)
				counts->crowded++;
			continue;
		}
		double rim = 0;
		int nrim = 0;
		for (int y = y0; y < y1; ++y) {
			const uint8_t *row = img.ptr<uint8_t>(y);
			const int *lab = s.labels.ptr<int>(y);
			for (int x = x0; x < x1; ++x)
				if ((y == y0 || y == y1 - 1 || x == x0 || x == x1 - 1) &&
				    lab[x] == 0) {
					rim += row[x];
					++nrim;
				}
		}
		const double bg = nrim ? rim / nrim : 0.0;
		double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
		for (int y = y0; y < y1; ++y) {
			const uint8_t *row = img.ptr<uint8_t>(y);
			for (int x = x0; x < x1; ++x) {
				double w = row[x] - bg;
				sw += w;
				sx += w * x;
				sy += w * y;
				sxx += w * x * x;
				syy += w * y * y;
				sxy += w * x * y;
			}
		}
		if (!(sw > 0))
			continue;
		double cx = sx / sw, cy = sy / sw;
		double a = sxx / sw - cx * cx, c = syy / sw - cy * cy, b = sxy / sw - cx * cy;
		double tr = a + c,
		       disc = std::sqrt(std::max(0.0, 0.25 * (a - c) * (a - c) + b * b));
		double l1 = 0.5 * tr + disc, l2 = 0.5 * tr - disc;
		double aspect = l2 > 1e-12 ? std::sqrt(l1 / l2) : INFINITY;
		if (!(aspect <= d.max_aspect))
			continue;
		out.push_back({cx, cy, (double)area, aspect});
	}
	std::sort(out.begin(), out.end(), [](const rs_optical_blob &p, const rs_optical_blob &q) {
		return p.area_px > q.area_px;
	});
}

} // namespace rs_optical

using namespace rs_optical;

extern "C" enum rs_status rs_optical_detect(const struct rs_optical_detect_desc *desc,
                                            const struct rs_optical_image *img,
                                            struct rs_optical_blob *out, size_t cap, size_t *out_n,
                                            struct rs_error *err)
{
	RS_ASSERT(img && out_n && (!cap || out));
	*out_n = 0;
	rs_status st = check_image(img, err);
	if (st != RS_OK)
		return st;
	rs_optical_detect_desc d;
	resolve_detect(desc, &d);
	if (!detect_desc_valid(d))
		return rs_error_set(err, RS_ERR_INVALID, "detect: bad descriptor");
	DetectScratch s;
	std::vector<rs_optical_blob> blobs;
	try {
		detect(wrap(*img), d, s, blobs, nullptr);
	} catch (const cv::Exception &e) {
		return rs_error_set(err, RS_ERR_NO_MEMORY, "detect: %.160s", e.msg.c_str());
	}
	size_t n = std::min(cap, blobs.size());
	std::copy(blobs.begin(), blobs.begin() + (long)n, out);
	*out_n = n;
	return RS_OK;
}
