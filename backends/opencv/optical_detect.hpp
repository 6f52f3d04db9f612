// Blob detection shared by rs_optical_detect() and the tracker (private).
#ifndef RS_OPTICAL_DETECT_HPP
#define RS_OPTICAL_DETECT_HPP

#include <opencv2/core.hpp>

#include <vector>

#include "raystream/rs_optical.h"

namespace rs_optical
{

// Buffers reused from frame to frame.
struct DetectScratch {
	cv::Mat binary, labels, stats, centroids;
};

void resolve_detect(const rs_optical_detect_desc *in, rs_optical_detect_desc *out);
bool detect_desc_valid(const rs_optical_detect_desc &d);
// How far beyond its thresholded pixels a spot's centroid window reaches (its flanks).
const int k_centroid_margin_px = 3;

// Blobs refused as measurements: window cut by the image edge, or shared with another
// bright region.
struct DetectCounts {
	uint32_t at_edge = 0, crowded = 0, masked = 0;
};

// One camera's mask as the detector tests it: the rectangles and, from a mask image, the
// integral image of its nonzero pixels.
struct Mask {
	const rs_optical_mask *rects = nullptr;
	cv::Mat sum; // CV_32S, (rows + 1) x (cols + 1); empty: no mask image
};

// Blobs of `img` passing the gates, largest first; `counts` (may be null) the refused ones;
// `mask` (may be null) the regions a blob's window must not touch.
void detect(const cv::Mat &img, const rs_optical_detect_desc &d, DetectScratch &s,
            std::vector<rs_optical_blob> &out, DetectCounts *counts, const Mask *mask = nullptr);

// Whether the window [x0, x1) x [y0, y1) overlaps a rectangle of `mask` or a masked pixel
// of its image (mask may be null).
bool window_masked(const Mask *mask, int x0, int y0, int x1, int y1);

} // namespace rs_optical

#endif
