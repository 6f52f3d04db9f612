// Stereo rig: the check, the FileStorage file (YAML or JSON) and checkerboard calibration.
#include "optical_internal.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace rs_optical
{

cv::Matx33d quat_to_R(const double q[4])
{
	double x = q[0], y = q[1], z = q[2], w = q[3];
	return cv::Matx33d(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
	                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
	                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y));
}

rs_status check_image(const rs_optical_image *img, rs_error *err)
{
	if (!img || !img->pixels || img->width < 1 || img->height < 1 || img->width > 16384 ||
	    img->height > 16384 || img->stride < (size_t)img->width)
		return rs_error_set(err, RS_ERR_INVALID, "optical: malformed image");
	return RS_OK;
}

} // namespace rs_optical

using namespace rs_optical;

static bool finite_all(const double *v, int n)
{
	for (int i = 0; i < n; ++i)
		if (!std::isfinite(v[i]))
			return false;
	return true;
}

extern "C" enum rs_status rs_optical_rig_check(const struct rs_optical_rig *rig,
                                               struct rs_error *err)
{
	RS_ASSERT(rig);
	for (int c = 0; c < 2; ++c) {
		const rs_optical_camera &k = rig->cam[c];
		if (k.width < 1 || k.height < 1 || k.width > 16384 || k.height > 16384)
			return rs_error_set(err, RS_ERR_BAD_DATA, "rig: camera %d image size %dx%d",
			                    c, k.width, k.height);
		if (!finite_all(k.K, 9) || !finite_all(k.dist, 5) || !(k.K[0] > 0) ||
		    !(k.K[4] > 0) || k.K[1] != 0 || k.K[3] != 0 || k.K[6] != 0 || k.K[7] != 0 ||
		    k.K[8] != 1)
			return rs_error_set(
			    err, RS_ERR_BAD_DATA,
			    "rig: camera %d matrix K is not [fx 0 cx; 0 fy cy; 0 0 1] "
			    "with finite fx, fy > 0 (or distortion not finite)",
			    c);
		if (!(k.K[2] >= 0 && k.K[2] <= k.width && k.K[5] >= 0 && k.K[5] <= k.height))
			return rs_error_set(err, RS_ERR_BAD_DATA,
			                    "rig: camera %d principal point outside the image", c);
	}
	if (!finite_all(rig->R_cam1_cam0, 9) || !finite_all(rig->t_cam1_cam0, 3))
		return rs_error_set(err, RS_ERR_BAD_DATA, "rig: non-finite extrinsics");
	cv::Matx33d R = R_of(*rig);
	if (cv::norm(R.t() * R - cv::Matx33d::eye(), cv::NORM_INF) > 1e-6 ||
	    std::fabs(cv::determinant(R) - 1.0) > 1e-6)
		return rs_error_set(err, RS_ERR_BAD_DATA, "rig: R_cam1_cam0 is not a rotation");
	if (!(cv::norm(t_of(*rig)) > 0.001))
		return rs_error_set(err, RS_ERR_BAD_DATA, "rig: baseline below 1 mm");
	return RS_OK;
}

extern "C" void rs_optical_rig_example(double baseline_m, int width, int height,
                                       struct rs_optical_rig *out)
{
	std::memset(out, 0, sizeof *out);
	for (int c = 0; c < 2; ++c) {
		rs_optical_camera &k = out->cam[c];
		k.width = width;
		k.height = height;
		double f = 1.25 * width;
		const double K[9] = {f, 0, 0.5 * (width - 1), 0, f, 0.5 * (height - 1), 0, 0, 1};
		std::memcpy(k.K, K, sizeof K);
	}
	// Camera 1's axes in camera 0's frame are the rows of R; its z axis towards (0, 0, 1).
	double a = std::atan2(baseline_m, 1.0), s = std::sin(a), c = std::cos(a);
	const double R[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
	std::memcpy(out->R_cam1_cam0, R, sizeof R);
	out->t_cam1_cam0[0] = -c * baseline_m; // t = -R C1, C1 = (baseline, 0, 0)
	out->t_cam1_cam0[1] = 0.0;
	out->t_cam1_cam0[2] = s * baseline_m;
}

static bool read_mat(const cv::FileNode &n, int rows, int cols, double *out)
{
	if (n.empty())
		return false;
	cv::Mat m;
	n >> m;
	if (m.empty() || m.total() != (size_t)(rows * cols) || m.channels() != 1)
		return false;
	m.convertTo(m, CV_64F);
	m = m.reshape(1, 1);
	for (int i = 0; i < rows * cols; ++i)
		out[i] = m.at<double>(0, i);
	return true;
}

extern "C" enum rs_status rs_optical_rig_load(const char *path, struct rs_optical_rig *out,
                                              struct rs_error *err)
{
	RS_ASSERT(path && out);
	if (access(path, R_OK) != 0)
		return rs_error_set(err, errno == ENOENT ? RS_ERR_NOT_FOUND : RS_ERR_IO,
		                    "rig: cannot open '%s': %s", path, strerror(errno));
	struct stat sb;
	if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
		return rs_error_set(err, RS_ERR_IO, "rig: '%s' is not a regular file", path);
	rs_optical_rig r;
	std::memset(&r, 0, sizeof r);
	const char *missing = nullptr;
	try {
		cv::FileStorage fs(path, cv::FileStorage::READ);
		if (!fs.isOpened())
			return rs_error_set(err, RS_ERR_PARSE,
			                    "rig: '%s' is not an OpenCV YAML/JSON file", path);
		for (int c = 0; c < 2 && !missing; ++c) {
			std::string s = std::to_string(c);
			double size[2] = {0, 0};
			if (!read_mat(fs["image_size" + s], 1, 2, size) ||
			    !(size[0] >= 1 && size[0] <= 16384 && size[1] >= 1 && size[1] <= 16384))
				missing = c ? "image_size1" : "image_size0";
			else if (!read_mat(fs["K" + s], 3, 3, r.cam[c].K))
				missing = c ? "K1" : "K0";
			else if (!read_mat(fs["dist" + s], 1, 5, r.cam[c].dist))
				missing = c ? "dist1" : "dist0";
			r.cam[c].width = (int)size[0];
			r.cam[c].height = (int)size[1];
		}
		if (!missing && !read_mat(fs["R"], 3, 3, r.R_cam1_cam0))
			missing = "R";
		if (!missing && !read_mat(fs["T"], 3, 1, r.t_cam1_cam0))
			missing = "T";
		if (!missing && !fs["rms"].empty())
			fs["rms"] >> r.rms_px;
	} catch (const cv::Exception &e) {
		return rs_error_set(err, RS_ERR_PARSE, "rig: '%s' is malformed: %.120s", path,
		                    e.msg.c_str());
	}
	if (missing)
		return rs_error_set(err, RS_ERR_PARSE, "rig: '%s': missing or malformed '%s'", path,
		                    missing);
	enum rs_status st = rs_optical_rig_check(&r, err);
	if (st != RS_OK)
		return st;
	*out = r;
	return RS_OK;
}

static bool ends_with(const std::string &s, const char *suffix)
{
	size_t n = std::strlen(suffix);
	return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

// Write through `path.tmp-XXXXXX` renamed over `path` when complete; only a regular file
// (or nothing) is replaced, as everywhere in raystream.
template <class Writer> static rs_status atomic_write(const char *path, Writer write, rs_error *err)
{
	struct stat sb;
	if (lstat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
		return rs_error_set(err, RS_ERR_IO, "cannot write %s: not a regular file", path);
	std::string tmp = std::string(path) + ".tmp-XXXXXX";
	int fd = mkstemp(&tmp[0]);
	if (fd < 0)
		return rs_error_set(err, RS_ERR_IO, "cannot create %s: %s", path, strerror(errno));
	(void)fchmod(fd, 0644);
	close(fd);
	bool ok = false;
	try {
		ok = write(tmp);
	} catch (const cv::Exception &) {
		ok = false;
	}
	if (!ok) {
		unlink(tmp.c_str());
		return rs_error_set(err, RS_ERR_IO, "cannot write %s", path);
	}
	if (rename(tmp.c_str(), path) != 0) {
		int e = errno;
		unlink(tmp.c_str());
		return rs_error_set(err, RS_ERR_IO, "cannot write %s: %s", path, strerror(e));
	}
	return RS_OK;
}

extern "C" enum rs_status rs_optical_rig_save(const char *path, const struct rs_optical_rig *rig,
                                              struct rs_error *err)
{
	RS_ASSERT(path && rig);
	enum rs_status st = rs_optical_rig_check(rig, err);
	if (st != RS_OK)
		return st;
	std::string p(path);
	int format = cv::FileStorage::FORMAT_YAML;
	if (ends_with(p, ".json"))
		format = cv::FileStorage::FORMAT_JSON;
	else if (!ends_with(p, ".yaml") && !ends_with(p, ".yml"))
		return rs_error_set(err, RS_ERR_INVALID,
		                    "rig: '%s' must end in .yaml, .yml or .json", path);
	return atomic_write(
	    path,
	    [&](const std::string &tmp) {
		    cv::FileStorage fs(tmp, cv::FileStorage::WRITE | format);
		    if (!fs.isOpened())
			    return false;
		    for (int c = 0; c < 2; ++c) {
			    std::string s = std::to_string(c);
			    const rs_optical_camera &k = rig->cam[c];
			    fs << "image_size" + s << cv::Mat(cv::Matx12d(k.width, k.height));
			    fs << "K" + s << cv::Mat(K_of(k));
			    fs << "dist" + s << dist_of(k);
		    }
		    fs << "R" << cv::Mat(R_of(*rig));
		    fs << "T" << cv::Mat(t_of(*rig));
		    fs << "rms" << rig->rms_px;
		    fs.release();
		    return true;
	    },
	    err);
}

extern "C" enum rs_status rs_optical_write_png(const char *path, const uint8_t *pixels, int width,
                                               int height, struct rs_error *err)
{
	RS_ASSERT(path && pixels);
	if (width < 1 || height < 1)
		return rs_error_set(err, RS_ERR_INVALID, "png: bad arguments");
	cv::Mat m(height, width, CV_8UC1, const_cast<uint8_t *>(pixels));
	// imwrite picks the codec from the name, which the temporary name hides: encode first.
	std::vector<uchar> png;
	if (!cv::imencode(".png", m, png))
		return rs_error_set(err, RS_ERR_IO, "png: cannot encode %s", path);
	return atomic_write(
	    path,
	    [&](const std::string &tmp) {
		    FILE *f = fopen(tmp.c_str(), "wb");
		    if (!f)
			    return false;
		    bool ok = fwrite(png.data(), 1, png.size(), f) == png.size();
		    return (fclose(f) == 0) && ok;
	    },
	    err);
}
