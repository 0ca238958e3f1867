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
  // The keypoints. Square markers: the four corners of the square, in the canonical order
  // top-left, top-right, bottom-right, bottom-left. Boards: N points, as keypoints_marker says.
  std::vector<Vec2> corners_px;
  // Where each keypoint lies on the marker, in its marker frame (origin at the centre, x to the
  // right, y up on the print) in units of the marker size. Empty for square markers: their
  // corners, (-0.5, 0.5), (0.5, 0.5), (0.5, -0.5), (-0.5, -0.5).
  std::vector<Vec2> keypoints_marker;
  // Where the marker lies in the image when its keypoints do not span it (a ring marker's one
  // keypoint, its centre): a polygon inside which its plane is fitted. Empty: the keypoints'
  // outline.
  std::vector<Vec2> outline_px;
  int hamming = 0;             // bits corrected while decoding
  double decision_margin = 0;  // back-end's decoding confidence (AprilTag: mean bit margin)
};

// The keypoints' marker-frame coordinates in metres (z = 0) for a marker of edge `size`.
std::vector<Vec3> marker_frame_keypoints(const Detection& detection, double size);

// The keypoints' outline in the image: the corners of a square marker, the convex hull of a
// board's keypoints, `outline_px` where given (what the marker plane is fitted inside).
std::vector<Vec2> keypoint_outline(const Detection& detection);

// Options of the AprilTag 3 back-end (libapriltag's detector fields).
struct AprilTagOptions {
  float decimate = 1.0f;  // LiDAR images are small: full resolution by default
  float sigma = 0.0f;     // Gaussian blur of the segmentation image
  bool refine_edges = true;
  double decode_sharpening = 0.25;
  int max_hamming = -1;  // bits to correct; -1 = per-family default (see docs/detectors.md)
  // On a binary image, run libapriltag only on the boxes around quad-shaped black-white
  // boundaries (src/detectors/search_regions.hpp; docs/detectors.md) instead of on every pixel.
  // Needs decimate 1 and sigma 0; the whole image is searched otherwise.
  bool search_regions = true;
  // With search_regions: a region whose outermost quad-shaped boundaries all span at least this
  // many pixels a cell of the family's black square has its quads found at half resolution
  // (libapriltag's quad_decimate 2; edges are still refined and cells read at full resolution).
  // A VLP-16's 17 cm tag at 1 m spans 10 pixels a cell: its frame's instructions fall 13 %.
  // 0 = never (docs/detectors.md, "Large outlines at half resolution").
  double half_resolution_px_per_cell = 6;
  // Given the binary image and the gray one it was thresholded from (DetectorImages): where a
  // search region's binary pixels decode nothing, run libapriltag again on its gray pixels
  // (those without a value keep their binary class; regions where under a fifth hold a value are
  // skipped). Its own local threshold reads cells 1.5-2 pixels wide that one global threshold
  // breaks up: OS1-128, 40 cm tag36h11 at 5 m, 19 of 20 scans against 11 (docs/detectors.md,
  // "Gray pixels where the binary ones decode nothing").
  bool decode_gray = true;
};

// Corner refinement of the ArUco back-end (OpenCV's CORNER_REFINE_*).
enum class ArucoRefine { kNone, kSubpixel, kContour, kAprilTag };

// Options of the ArUco back-end (OpenCV's DetectorParameters, LiDAR-sized defaults) and of iilfm's
// plausibility filter applied to its detections (see docs/detectors.md).
struct ArucoOptions {
  // Adaptive threshold windows (pixels, odd): small, because markers are 15-60 px wide.
  int window_min = 3;
  int window_max = 23;
  int window_step = 10;
  double threshold_constant = 7;
  // Contour line fitting is the most accurate on binarised images (docs/detectors.md).
  ArucoRefine refine = ArucoRefine::kContour;
  int refine_window = 3;  // half-size (pixels) of the subpixel refinement window
  // Marker perimeter limits relative to the image's larger side (OpenCV's rates); the default
  // minimum is low because LiDAR images are wide and markers small, the filter below decides.
  double min_perimeter_rate = 0.01;
  double max_perimeter_rate = 4.0;
  double error_correction_rate = 0.6;
  // Plausibility filter: reject quads whose shortest side spans fewer than min_cell_px pixels per
  // cell of the black square, whose longest side exceeds max_side_ratio times the shortest, or
  // whose one-cell margin is brighter than the black border next to it along fewer than
  // min_quiet_zone of its cells (a printed marker sits on white paper).
  double min_cell_px = 2.0;
  double max_side_ratio = 3.0;
  double min_quiet_zone = 0.75;
  // As AprilTagOptions::search_regions: on a binary image, detect only around quad-shaped
  // black-white boundaries.
  bool search_regions = true;
};

// Options of the concentric-ring back-end (docs/detectors.md, "Concentric rings").
struct RingsOptions {
  int max_hamming = 1;              // data rings to correct (the codes are 3 apart)
  double min_ring_px = 1.5;         // narrowest ring width (pixels) worth decoding
  double min_contrast = 0.25;       // white minus black ring means, of the gray scale
  double min_ring_agreement = 0.8;  // share of a ring's samples on its mean's side of mid-grey
};

struct DetectorOptions {
  AprilTagOptions apriltag;
  ArucoOptions aruco;
  RingsOptions rings;
};

// What the pipeline hands the detectors: the detection image and, when that is the binarised
// one, the gray image it was thresholded from (the same size) with the mask of its pixels that
// hold a value (observed or filled). Back-ends may find candidates on one and read codes from
// the other.
struct DetectorImages {
  cv::Mat image;  // CV_8U: binary (0 or 255) unless binarisation is off
  cv::Mat gray;   // CV_8U, or empty
  cv::Mat valid;  // CV_8U, 255 where `gray` holds a value; empty with `gray`
  // When >= 0, only markers crossing this column are wanted (the strip across a full-circle
  // image's seam): a back-end may leave the rest of the image unsearched.
  int crossing_column = -1;
};

class MarkerDetector {
 public:
  virtual ~MarkerDetector() = default;
  // The family string this detector reports.
  virtual const std::string& family() const = 0;
  // Appends the markers found in an 8-bit single-channel image.
  virtual void detect(const cv::Mat& gray, std::vector<Detection>& out) = 0;
  // Appends the markers found in the pipeline's images. By default detect(images.image, out);
  // AprilTag decodes the gray image inside the binary image's search regions
  // (AprilTagOptions::decode_gray).
  virtual void detect_images(const DetectorImages& images, std::vector<Detection>& out) {
    detect(images.image, out);
  }
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
  int min_distance = 0;  // smallest Hamming distance between two codes (0 = unknown)
  int ids = 0;           // the family's ids are 0 .. ids - 1
};
FamilyLayout family_layout(const std::string& family);

}  // namespace iilfm
