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
// Blobs of `img` passing the gates, largest first.
void detect(const cv::Mat &img, const rs_optical_detect_desc &d, DetectScratch &s,
            std::vector<rs_optical_blob> &out);

} // namespace rs_optical

#endif
