// Intensity that means the same at every range and angle (`--normalise-intensity`). Many LiDARs
// report the raw strength of the return (Ouster's photon-count `intensity`): it falls with the
// square of the range beyond the near field and with the cosine of the angle of incidence, so one
// threshold cannot split black print from white paper at 2 m and at 12 m. Normalisation turns the
// projected intensity image into what each surface would return head-on at a reference range.
// Only the detector's image changes: no 3-D point and no projected image is altered.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace iilfm {

struct ProjectedImage;

enum class IntensityNormalisation {
  kNone,            // intensity as the sensor reports it (calibrated reflectivity: Livox, Velodyne)
  kRange,           // times (range / reference)^2
  kRangeIncidence,  // and divided by the cosine of the angle of incidence
};

// "none", "range", "range-incidence".
const char* to_string(IntensityNormalisation mode);

struct NormalisationOptions {
  IntensityNormalisation mode = IntensityNormalisation::kNone;
  // Range at which normalised and reported intensities agree: a fixed threshold with
  // normalisation is the intensity a surface returns head-on at this range.
  double reference_m = 10;
  // Smallest cosine corrected (at most a 5x gain). A steeper estimate is taken for a depth edge
  // inside the normal's window and left uncorrected, so edges do not glow; surfaces seen at more
  // than 78 deg keep their raw falloff.
  double min_cos_incidence = 0.2;
  // Half-width in degrees of the window the normal is estimated over (at least one pixel each
  // way): the difference of the mean range on either side, so range noise averages out.
  double normal_half_window_deg = 1.0;
};

// Reused images of the incidence estimate (no allocation once warm).
struct NormalisationBuffers {
  cv::Mat weight, range_sum, weight_sum, cos_incidence;
  cv::Mat weighted_col, weighted_row, col_sum, row_sum;  // window centroids
  cv::Mat across[3];  // window sums along rows (of the range, weight and column images)
};

// Writes the normalised intensity (CV_32F, 0 where unobserved) of `image` into `out`. With
// IntensityNormalisation::kNone it does nothing. With `threads` > 1, images of at least 128k
// pixels are split between threads by rows: the same image for any count.
void normalise_intensity(const ProjectedImage& image, const NormalisationOptions& options,
                         NormalisationBuffers& work, cv::Mat& out, int threads = 1);

// Cosine of the angle of incidence per pixel (CV_32F; 1 where unobserved, unknown or at a depth
// edge), estimated from the range image alone: exposed for tests.
void estimate_cos_incidence(const ProjectedImage& image, const NormalisationOptions& options,
                            NormalisationBuffers& work, cv::Mat& cos_incidence, int threads = 1);

}  // namespace iilfm
