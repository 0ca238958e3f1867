// Preprocessing of the intensity image for visual fiducial detectors (paper Sec. III-C):
// optional normalisation of the intensity for range and incidence, scaling to 8-bit gray, hole
// filling for the detector's image only, naive global threshold, optional Gaussian blur.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "iilfm/detector.hpp"
#include "iilfm/intensity_normalisation.hpp"
#include "iilfm/projection.hpp"

namespace iilfm {

struct PreprocessOptions {
  // Intensity for range and incidence before anything else (intensity_normalisation.hpp); the
  // threshold is then in normalised units. Off: no pass, no cost.
  NormalisationOptions normalise;
  // Naive threshold in the cloud's intensity units; unset = Otsu's threshold over observed pixels.
  std::optional<double> threshold;
  // When `threshold` lies above every observed intensity, no pixel can be white: the cloud's
  // intensity is not on the scale the threshold was set for (reflectance in 0..1, as KITTI's files
  // and many conversions hold it, against a preset's 0..255). Otsu's threshold is then used and
  // PreprocessedImage::replaced_threshold says so. A preset's threshold may be replaced; one the
  // user gives (set_threshold, Python threshold=) is kept.
  bool replace_threshold_above_all = true;
  // Local threshold (`--threshold local`): a pixel is white when brighter than the mean of the
  // local_window x local_window pixels around it, wherever that window's intensity spread (standard
  // deviation) exceeds local_min_contrast of the 99th percentile of observed intensity; flat
  // regions keep the global threshold above. One threshold then serves markers lit or printed
  // differently across a scene.
  bool local_threshold = false;
  int local_window = 15;
  double local_min_contrast = 0.1;
  bool binarize = true;    // the paper's mandatory binarisation
  bool fill_holes = true;  // give unobserved pixels the mean of their observed 8-neighbours
  int fill_min_neighbours = 3;
  // Filling passes; each pass may use the values the previous one filled in, so sparse images
  // (a Livox after few frames) close up without widening the holes' surroundings much.
  int fill_passes = 2;
  // Resample coarse or ring rows so the detector sees square pixels
  // (include/iilfm/square_pixels.hpp).
  bool square_pixels = true;
  double blur_sigma = 0;     // Gaussian blur (pixels) after thresholding; 0 = off
  int unobserved_value = 0;  // gray value of pixels still unobserved after filling
  // Binary image: a pixel still unobserved after filling takes the class (black or white) of most
  // observed pixels in its block of this many pixels square and the 8 blocks around, white when
  // there is none; 0 gives every such pixel `unobserved_value` instead. At most 64.
  int hole_class_block = 2;
  // Threads for hole filling, the gray image and the threshold, each taking a part of the rows
  // (at least 64k pixels): the same images for any count. `--threads` sets it.
  int threads = 1;
};

// classify_holes' counts (src/hole_classes.hpp): per column, per block, each block with its left
// and right ones for three bands of rows and a band of zeros, the class per block and per column.
struct HoleClassBuffers {
  std::vector<std::uint16_t> column_white, column_observed, block_white, block_observed;
  std::vector<std::uint16_t> across_white, across_observed;
  std::vector<std::uint8_t> block_class, hole_row, band_has_hole;
};

// The detector's images. They share the projected image's geometry, or, with square pixels, have
// their own: detections are in `geometry`'s coordinates (map_pixel converts them).
struct PreprocessedImage {
  ImageGeometry geometry;
  cv::Mat gray;          // CV_8U intensity scaled to 0..255 (display, gray decoding), holes filled
  cv::Mat detect;        // CV_8U image handed to the detectors (binary unless binarize=false)
  cv::Mat valid;         // CV_8U 255 where observed or filled, 0 where still unobserved
  double threshold = 0;  // threshold applied, in intensity units
  // Whether the fixed threshold lay above every observed intensity, that largest intensity (set
  // whenever the threshold was above the 99th percentile), and the threshold when Otsu's replaced
  // it (PreprocessOptions::replace_threshold_above_all).
  bool threshold_above_all = false;
  double max_intensity = 0;
  std::optional<double> replaced_threshold;
  // Every observed intensity is 0 (or below): the cloud carries no intensity (no intensity,
  // reflectivity or i field), so no threshold can show a marker.
  bool no_intensity = false;
  // Intensity mapped to gray 255: twice the 99th percentile of the observed intensity, so white
  // paper is not clipped where walls fill most of the image.
  double intensity_scale = 0;
  // The values the threshold was applied to (a header onto a working buffer, the normalised or the
  // projected intensity: valid until the next frame), for binarize_at.
  cv::Mat filled;

  // Working buffers (hole filling, square pixels), kept so that frame after frame of one size
  // allocates nothing.
  struct Buffers {
    cv::Mat values, mask;
  };
  Buffers work[2];
  HoleClassBuffers hole_classes;
  // Per row of the detector's images: 1 where it repeats the row above (square pixels copy most
  // rows of a spinning LiDAR's image), so per-pixel passes copy it instead.
  std::vector<std::uint8_t> repeats_row_above;
  cv::Mat normalised;  // the normalised intensity (when normalisation is on)
  NormalisationBuffers normalise_work;
};

// Fills `out`, reusing its buffers.
void preprocess(const ProjectedImage& image, const PreprocessOptions& options,
                PreprocessedImage& out);

// Otsu's threshold over `image`'s observed gray values, in the units of its threshold.
double otsu_threshold(const PreprocessedImage& image);

// The binary image preprocess makes with the naive threshold `threshold` (holes taking their
// surroundings' class, the blur), written to `detect`: a second threshold for the same frame
// without redoing the rest.
void binarize_at(PreprocessedImage& image, double threshold, const PreprocessOptions& options,
                 cv::Mat& detect);

// The same with the local threshold (PreprocessOptions::local_threshold; `image.threshold` in
// the flat regions).
void binarize_locally(PreprocessedImage& image, const PreprocessOptions& options, cv::Mat& detect);

// What the detectors are given (headers onto `image`'s buffers, no copy): the detection image,
// and with a binarised one the gray image and its valid mask.
DetectorImages detector_images(const PreprocessedImage& image, const PreprocessOptions& options);

}  // namespace iilfm
