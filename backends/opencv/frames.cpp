// Grey frame streams from image sequences, video files and V4L2 cameras (cv::VideoCapture).
#include "optical_internal.hpp"

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <cstdlib>
#include <new>
#include <string>

struct rs_optical_frames {
	cv::VideoCapture cap;
	cv::Mat frame, grey;
	bool camera = false;
	uint64_t count = 0;
};

extern "C" enum rs_status rs_optical_frames_open(const char *what, int camera,
                                                 struct rs_optical_frames **out,
                                                 struct rs_error *err)
{
	RS_ASSERT(what && out);
	*out = nullptr;
	// The library is silent (errors come back through rs_error); OpenCV would otherwise
	// log a warning to stderr at the end of every image sequence.
	cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
	rs_optical_frames *f = new (std::nothrow) rs_optical_frames();
	if (!f)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "frames: out of memory");
	f->camera = camera != 0;
	std::string w(what);
	bool ok = false;
	try {
		if (camera) {
			char *end = nullptr;
			long idx = std::strtol(what, &end, 10);
			ok = *what && !*end && idx >= 0 && idx < 64
			         ? f->cap.open((int)idx, cv::CAP_V4L2)
			         : f->cap.open(w, cv::CAP_V4L2);
		} else if (w.find('%') != std::string::npos) {
			// A printf pattern is an image sequence; anything else a video file. Naming
			// the backend keeps OpenCV from trying every other one.
			ok = f->cap.open(w, cv::CAP_IMAGES);
		} else {
			ok = f->cap.open(w, cv::CAP_FFMPEG);
		}
	} catch (const cv::Exception &) {
		ok = false;
	}
	if (!ok) {
		delete f;
		return rs_error_set(err, camera ? RS_ERR_NOT_FOUND : RS_ERR_IO,
		                    "%s: cannot open '%.200s'", camera ? "cam" : "video", what);
	}
	*out = f;
	return RS_OK;
}

extern "C" enum rs_status rs_optical_frames_read(struct rs_optical_frames *f,
                                                 struct rs_optical_image *out, struct rs_error *err)
{
	RS_ASSERT(f && out);
	bool ok = false;
	try {
		ok = f->cap.read(f->frame) && !f->frame.empty();
		if (ok) {
			if (f->frame.channels() == 3)
				cv::cvtColor(f->frame, f->grey, cv::COLOR_BGR2GRAY);
			else if (f->frame.channels() == 4)
				cv::cvtColor(f->frame, f->grey, cv::COLOR_BGRA2GRAY);
			else if (f->frame.depth() != CV_8U)
				f->frame.convertTo(f->grey, CV_8U);
			else
				f->grey = f->frame;
		}
	} catch (const cv::Exception &e) {
		return rs_error_set(err, RS_ERR_IO, "frames: frame %llu: %.120s",
		                    (unsigned long long)f->count, e.msg.c_str());
	}
	if (!ok) {
		if (f->count == 0)
			return rs_error_set(err, RS_ERR_IO, "frames: cannot read the first frame");
		if (f->camera)
			return rs_error_set(err, RS_ERR_DISCONNECTED, "cam: camera stopped");
		return rs_error_set(err, RS_END, "frames: end of stream");
	}
	f->count++;
	*out = {f->grey.data, f->grey.cols, f->grey.rows, f->grey.step[0]};
	return RS_OK;
}

extern "C" void rs_optical_frames_destroy(struct rs_optical_frames **frames)
{
	if (!frames)
		return;
	delete *frames;
	*frames = nullptr;
}
