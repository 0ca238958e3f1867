// The plug-in interface of 2-D marker detectors, and the registry that maps family strings
// ("apriltag:tag36h11", ...) to back-ends.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm {

// One decoded marker in image coordinates (pixel centres at integer coordinates).
struct Detection {
  std::string family;  // e.g. "apriltag:tag36h11"
  int id = -1;
  std::vector<Vec2> corners_px;  // canonical order: top-left, top-right, bottom-right, bottom-left
  int hamming = 0;               // bits corrected while decoding
  double decision_margin = 0;    // back-end's decoding confidence (AprilTag: mean bit margin)
};

// Options of the AprilTag 3 back-end (libapriltag's detector fields).
struct AprilTagOptions {
  float decimate = 1.0f;  // LiDAR images are small: full resolution by default
  float sigma = 0.0f;     // Gaussian blur of the segmentation image
  int threads = 1;
  bool refine_edges = true;
  double decode_sharpening = 0.25;
  int max_hamming = -1;  // bits to correct; -1 = per-family default (see docs/detectors.md)
};

struct DetectorOptions {
  AprilTagOptions apriltag;
};

class MarkerDetector {
 public:
  virtual ~MarkerDetector() = default;
  // The family string this detector reports.
  virtual const std::string& family() const = 0;
  // Appends the markers found in an 8-bit single-channel image.
  virtual void detect(const cv::Mat& gray, std::vector<Detection>& out) = 0;
};

// A detector for `family`; InputError for unknown back-ends or families.
std::unique_ptr<MarkerDetector> make_detector(const std::string& family,
                                              const DetectorOptions& options = {});

// Every family string the registered back-ends accept.
std::vector<std::string> known_families();

// Marker geometry of a family: the printed image is total_width cells wide, the outer black
// square (whose corners are reported) is border_width cells wide.
struct FamilyLayout {
  int border_width = 0;
  int total_width = 0;
};
FamilyLayout family_layout(const std::string& family);

}  // namespace iilfm
