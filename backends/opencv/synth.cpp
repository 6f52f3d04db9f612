// Synthetic frames for tests and the video: source: what the rig sees of the markers at a
// known pose, with noise, blur, a dim or occluded marker, a stray light and a reflection;
// and checkerboard views for calibration.
#include "optical_internal.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace rs_optical;

// Camera-0 frame point into camera v's pixel coordinates (with distortion), and depth.
static bool project(const rs_optical_rig &rig, int v, const cv::Vec3d &X0, cv::Point2d *px,
                    double *depth)
{
	cv::Vec3d X = v ? R_of(rig) * X0 + t_of(rig) : X0;
	if (!(X[2] > 1e-6))
		return false;
	std::vector<cv::Point3d> in{cv::Point3d(X[0], X[1], X[2])};
	std::vector<cv::Point2d> out;
	cv::projectPoints(in, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K_of(rig.cam[v]),
	                  dist_of(rig.cam[v]), out);
	*px = out[0];
	*depth = X[2];
	return true;
}

// A disc of radius r (px) at c, integrated over each pixel by 8 x 8 supersampling, so the
// image centroid is c (pixel centres at integer coordinates).
static void draw_disc(cv::Mat &img, cv::Point2d c, double r, double level)
{
	int x0 = std::max(0, (int)std::floor(c.x - r - 1)),
	    x1 = std::min(img.cols - 1, (int)std::ceil(c.x + r + 1));
	int y0 = std::max(0, (int)std::floor(c.y - r - 1)),
	    y1 = std::min(img.rows - 1, (int)std::ceil(c.y + r + 1));
	const int n = 8;
	for (int y = y0; y <= y1; ++y)
		for (int x = x0; x <= x1; ++x) {
			int hit = 0;
			for (int sy = 0; sy < n; ++sy)
				for (int sx = 0; sx < n; ++sx) {
					double dx = x - 0.5 + (sx + 0.5) / n - c.x;
					double dy = y - 0.5 + (sy + 0.5) / n - c.y;
					hit += dx * dx + dy * dy <= r * r;
				}
			img.at<float>(y, x) += (float)(level * hit / (n * n));
		}
}

static void finish(cv::Mat &f, const rs_optical_synth_desc &d, uint64_t seed, uint8_t *out)
{
	if (d.blur_px > 0)
		cv::GaussianBlur(f, f, cv::Size(0, 0), d.blur_px);
	if (d.noise_grey > 0) {
		cv::RNG rng(seed ? seed : 1);
		cv::Mat n(f.size(), CV_32F);
		rng.fill(n, cv::RNG::NORMAL, 0.0, d.noise_grey);
		f += n;
	}
	cv::Mat o(f.rows, f.cols, CV_8UC1, out);
	f.convertTo(o, CV_8U); // rounds and saturates to 0..255
}

extern "C" enum rs_status rs_optical_synth_render(const struct rs_optical_rig *rig,
                                                  const struct rs_pose_layout *layout,
                                                  const struct rs_pose *T_cam0_markers,
                                                  const struct rs_optical_synth_desc *desc,
                                                  uint8_t *out0, uint8_t *out1,
                                                  struct rs_error *err)
{
	RS_ASSERT(rig && layout && T_cam0_markers && out0 && out1);
	enum rs_status st = rs_optical_rig_check(rig, err);
	if (st != RS_OK)
		return st;
	rs_optical_synth_desc d = desc ? *desc : rs_optical_synth_desc{};
	if (d.marker_radius_m == 0)
		d.marker_radius_m = 0.004;
	if (d.background_grey == 0)
		d.background_grey = 10;
	if (d.peak_grey == 0)
		d.peak_grey = 230;
	if (!(d.marker_radius_m > 0) || !(d.noise_grey >= 0) || !(d.blur_px >= 0) ||
	    !std::isfinite(d.noise_grey + d.blur_px + d.background_grey + d.peak_grey))
		return rs_error_set(err, RS_ERR_INVALID, "synth: bad descriptor");
	cv::Matx33d R = quat_to_R(T_cam0_markers->orientation);
	cv::Vec3d t(T_cam0_markers->position);
	// Lights 0-2: the markers; 3: the layout's verifier (id 3: dim_marker and
	// occluded_marker 4 name it); 4: the stray lamp.
	cv::Vec3d X[5];
	for (int i = 0; i < 3; ++i)
		X[i] = R * cv::Vec3d(layout->markers[i]) + t;
	X[3] = R * cv::Vec3d(layout->verifier) + t;
	// The stray lamp: marker-sized, 12 cm beside the triangle, in both views (so it also
	// lies on its epipolar line and triangulates, just not at the layout's distances).
	X[4] = X[0] + R * cv::Vec3d(-0.12, 0.05, 0.0);
	uint8_t *outs[2] = {out0, out1};
	for (int v = 0; v < 2; ++v) {
		const rs_optical_camera &c = rig->cam[v];
		cv::Mat f(c.height, c.width, CV_32F, cv::Scalar(d.background_grey));
		cv::Point2d first(-1, -1);
		for (int i = 0; i < 5; ++i) {
			if ((i == 3 && !layout->has_verifier) || (i == 4 && !d.stray_light))
				continue;
			if (v == 1 && d.occluded_marker == i + 1)
				continue;
			cv::Point2d px;
			double z;
			if (!project(*rig, v, X[i], &px, &z))
				continue;
			if (i == 0)
				first = px;
			double level = d.peak_grey - d.background_grey;
			if (d.dim_marker == i + 1)
				level *= 0.5;
			draw_disc(f, px, c.K[0] * d.marker_radius_m / z, level);
		}
		if (d.reflection && first.x >= 0) {
			// A specular streak off the display's edge: bright, thin and long.
			cv::ellipse(f, cv::Point((int)first.x + 25, (int)first.y + 30),
			            cv::Size(14, 2), 30.0, 0.0, 360.0, cv::Scalar(d.peak_grey),
			            cv::FILLED, cv::LINE_AA);
		}
		finish(f, d, d.seed * 2 + (uint64_t)v + 1, outs[v]);
	}
	return RS_OK;
}

extern "C" enum rs_status rs_optical_synth_board(const struct rs_optical_rig *rig,
                                                 const struct rs_optical_board *board,
                                                 const struct rs_pose *T_cam0_board, uint8_t *out0,
                                                 uint8_t *out1, struct rs_error *err)
{
	RS_ASSERT(rig && board && T_cam0_board && out0 && out1);
	enum rs_status st = rs_optical_rig_check(rig, err);
	if (st != RS_OK)
		return st;
	// The board texture: (cols + 1) x (rows + 1) squares plus a white quiet zone of one
	// square, at 16 texels per square; texel (u, v) centre = board point ((u + .5) / 16 - 1) s.
	const int tex = 16, nx = board->cols + 3, ny = board->rows + 3;
	const double s = board->square_m;
	cv::Mat texture(ny * tex, nx * tex, CV_8UC1, cv::Scalar(255));
	for (int r = 0; r < board->rows + 1; ++r)
		for (int c = 0; c < board->cols + 1; ++c)
			if ((r + c) % 2 == 0)
				texture(cv::Rect((c + 1) * tex, (r + 1) * tex, tex, tex)).setTo(0);
	cv::Matx33d R = quat_to_R(T_cam0_board->orientation);
	cv::Vec3d t(T_cam0_board->position);
	uint8_t *outs[2] = {out0, out1};
	for (int v = 0; v < 2; ++v) {
		const rs_optical_camera &c = rig->cam[v];
		// Texel -> board (metres; first inner corner at the origin) -> camera -> pixels.
		cv::Matx33d T_board_tex(s / tex, 0, -2 * s, 0, s / tex, -2 * s, 0, 0, 1);
		cv::Matx33d Rv = v ? R_of(*rig) * R : R;
		cv::Vec3d tvv = v ? R_of(*rig) * t + t_of(*rig) : t;
		cv::Matx33d H_cam_board(Rv(0, 0), Rv(0, 1), tvv[0], Rv(1, 0), Rv(1, 1), tvv[1],
		                        Rv(2, 0), Rv(2, 1), tvv[2]);
		// Pixel centres at integers; texel centres at (u + 0.5): shift by half a texel.
		cv::Matx33d half(1, 0, 0.5, 0, 1, 0.5, 0, 0, 1);
		cv::Matx33d H = K_of(c) * H_cam_board * T_board_tex * half;
		cv::Point2d corners[4] = {{0, 0},
		                          {(double)nx * tex, 0},
		                          {0, (double)ny * tex},
		                          {(double)nx * tex, (double)ny * tex}};
		for (const cv::Point2d &p : corners) {
			cv::Vec3d q = H * cv::Vec3d(p.x - 0.5, p.y - 0.5, 1);
			if (!(q[2] > 0) || q[0] / q[2] < 0 || q[1] / q[2] < 0 ||
			    q[0] / q[2] > c.width || q[1] / q[2] > c.height)
				return rs_error_set(
				    err, RS_ERR_DEGENERATE,
				    "synth board: board not wholly in view of camera %d", v);
		}
		cv::Mat o(c.height, c.width, CV_8UC1, outs[v]);
		cv::warpPerspective(texture, o, cv::Mat(H), o.size(), cv::INTER_LINEAR,
		                    cv::BORDER_CONSTANT, cv::Scalar(128));
	}
	return RS_OK;
}
