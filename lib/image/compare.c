/* Accuracy figures of an image against the CPU reference. */
#include <math.h>

#include "raystream/rs_image.h"

void rs_image_compare(const float *test, const float *reference, uint32_t width, uint32_t height,
                      uint32_t channels, double peak, double bad_threshold,
                      struct rs_image_diff *out)
{
	size_t pixels = (size_t)width * height;
	double sum_sq = 0.0, sum_abs = 0.0, max_err = 0.0;
	size_t bad = 0, mismatched = 0, samples = 0;
	for (size_t p = 0; p < pixels; ++p) {
		int is_bad = 0, is_mismatched = 0;
		for (uint32_t c = 0; c < channels; ++c) {
			double a = test[p * channels + c], b = reference[p * channels + c];
			if (isinf(a) || isinf(b)) {
				if (a != b)
					is_mismatched = 1;
				continue;
			}
			/* NaN in a test image is the worst error there is: count it as such. */
			double d = isnan(a) || isnan(b) ? INFINITY : fabs(a - b);
			if (d > max_err)
				max_err = d;
			if (d > bad_threshold)
				is_bad = 1;
			sum_sq += isinf(d) ? peak * peak : d * d;
			sum_abs += isinf(d) ? peak : d;
			samples++;
		}
		mismatched += (size_t)is_mismatched;
		bad += (size_t)(is_bad || is_mismatched);
	}
	out->pixels = pixels;
	out->mse = samples ? sum_sq / (double)samples : 0.0;
	out->psnr_db = out->mse > 0.0 ? 10.0 * log10(peak * peak / out->mse) : INFINITY;
	out->max_abs_error = max_err;
	out->bad_share = pixels ? (double)bad / (double)pixels : 0.0;
	out->mismatched = mismatched;
	out->mean_abs_error = samples ? sum_abs / (double)samples : 0.0;
}
