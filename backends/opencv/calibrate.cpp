// Checkerboard calibration of both cameras and of the pair (calibrateCamera, stereoCalibrate).
#include "optical_internal.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cstring>
#include <vector>

using namespace rs_optical;

static void copy_camera(const cv::Mat &K, const cv::Mat &d, cv::Size size, rs_optical_camera *c)
{
	c->width = size.width;
	c->height = size.height;
	for (int i = 0; i < 9; ++i)
		c->K[i] = K.at<double>(i / 3, i % 3);
	cv::Mat dd = d.reshape(1, 1);
	for (int i = 0; i < 5; ++i)
		c->dist[i] = i < (int)dd.total() ? dd.at<double>(0, i) : 0.0;
}

extern "C" enum rs_status rs_optical_calibrate(const struct rs_optical_board *board,
                                               const struct rs_optical_image *views0,
                                               const struct rs_optical_image *views1, size_t n,
                                               struct rs_optical_rig *out, size_t *out_used,
                                               struct rs_error *err)
{
	RS_ASSERT(out && (!n || (views0 && views1)));
	rs_optical_board b = board ? *board : rs_optical_board{};
	if (!b.cols)
		b.cols = 9;
	if (!b.rows)
		b.rows = 6;
	if (b.square_m == 0.0)
		b.square_m = 0.025;
	if (b.cols < 3 || b.rows < 3 || b.cols > 64 || b.rows > 64 || !(b.square_m > 0) ||
	    !(b.square_m < 10))
		return rs_error_set(err, RS_ERR_INVALID, "calibrate: bad board %dx%d, %g m", b.cols,
		                    b.rows, b.square_m);
	std::vector<cv::Point3f> model;
	for (int r = 0; r < b.rows; ++r)
		for (int c = 0; c < b.cols; ++c)
			model.emplace_back((float)(c * b.square_m), (float)(r * b.square_m), 0.0f);
	std::vector<std::vector<cv::Point3f>> obj;
	std::vector<std::vector<cv::Point2f>> pts[2];
	cv::Size size[2];
	cv::Size pattern(b.cols, b.rows);
	for (size_t i = 0; i < n; ++i) {
		const rs_optical_image *v[2] = {&views0[i], &views1[i]};
		std::vector<cv::Point2f> corners[2];
		bool found = true;
		for (int c = 0; c < 2 && found; ++c) {
			if (check_image(v[c], err) != RS_OK)
				return RS_ERR_INVALID;
			cv::Size s(v[c]->width, v[c]->height);
			if (size[c].area() && s != size[c])
				return rs_error_set(
				    err, RS_ERR_BAD_DATA,
				    "calibrate: view %zu of camera %d is %dx%d, not %dx%d", i, c,
				    s.width, s.height, size[c].width, size[c].height);
			size[c] = s;
			cv::Mat m = wrap(*v[c]);
			found = cv::findChessboardCorners(m, pattern, corners[c],
			                                  cv::CALIB_CB_ADAPTIVE_THRESH |
			                                      cv::CALIB_CB_NORMALIZE_IMAGE);
			if (found)
				cv::cornerSubPix(m, corners[c], cv::Size(5, 5), cv::Size(-1, -1),
				                 cv::TermCriteria(cv::TermCriteria::EPS +
				                                      cv::TermCriteria::COUNT,
				                                  50, 1e-4));
		}
		if (!found)
			continue;
		obj.push_back(model);
		pts[0].push_back(corners[0]);
		pts[1].push_back(corners[1]);
	}
	if (out_used)
		*out_used = obj.size();
	if (obj.size() < 5)
		return rs_error_set(err, RS_ERR_DEGENERATE,
		                    "calibrate: board found in %zu view pairs, need at least 5",
		                    obj.size());
	cv::Mat K[2], d[2], R, T, E, F;
	try {
		for (int c = 0; c < 2; ++c) {
			std::vector<cv::Mat> rv, tv;
			cv::calibrateCamera(obj, pts[c], size[c], K[c], d[c], rv, tv,
			                    cv::CALIB_FIX_K3);
		}
		double rms = cv::stereoCalibrate(obj, pts[0], pts[1], K[0], d[0], K[1], d[1],
		                                 size[0], R, T, E, F, cv::CALIB_FIX_INTRINSIC);
		std::memset(out, 0, sizeof *out);
		for (int c = 0; c < 2; ++c)
			copy_camera(K[c], d[c], size[c], &out->cam[c]);
		for (int i = 0; i < 9; ++i)
			out->R_cam1_cam0[i] = R.at<double>(i / 3, i % 3);
		for (int i = 0; i < 3; ++i)
			out->t_cam1_cam0[i] = T.at<double>(i, 0);
		out->rms_px = rms;
	} catch (const cv::Exception &e) {
		return rs_error_set(err, RS_ERR_DEGENERATE, "calibrate: %.160s", e.msg.c_str());
	}
	return rs_optical_rig_check(out, err);
}
