// ArUco back-end through OpenCV's aruco module (contrib, 4.6 API), for every predefined dictionary.
#pragma once

#include <memory>
#include <opencv2/aruco.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "iilfm/detector.hpp"

namespace iilfm::detail {

// `dictionary` is OpenCV's name ("DICT_4X4_50"); InputError if OpenCV does not predefine it.
std::unique_ptr<MarkerDetector> make_aruco_detector(const std::string& dictionary,
                                                    const ArucoOptions& options);

// InputError for inconsistent options; OpenCV's parameters for them.
void check_aruco_options(const ArucoOptions& options);
cv::Ptr<cv::aruco::DetectorParameters> aruco_parameters(const ArucoOptions& options);

// Moves OpenCV's marker corners, refined by `refine`, onto the black square's edge with pixel
// centres at integers (iilfm's convention).
void to_edge_convention(ArucoRefine refine, std::vector<Vec2>& corners);

// The black square is markerSize + 2 cells wide (one-cell border); drawMarker's users are told to
// leave a white margin, taken here as one cell on each side.
FamilyLayout aruco_layout(const std::string& dictionary);

// Moves every edge of a convex polygon outward by half the spacing of pixel-centre rows along it:
// from the outermost black pixel centres, where contour-based quads run, to the black edge.
void push_edges_outward(std::vector<Vec2>& corners);

// iilfm's plausibility check of a detected quad's shape (corners in order around the quad): false
// for slivers, quads too small to carry `border_width` cells, and non-convex quads.
bool plausible_marker_quad(const std::vector<Vec2>& corners, int border_width,
                           const ArucoOptions& options);

// Fraction of the cells of the one-cell margin around the black square (TL, TR, BR, BL corners,
// `border_width` cells wide) that are clearly brighter than the border cell next to them.
double quiet_zone_fraction(const cv::Mat& gray, const std::vector<Vec2>& corners, int border_width);

}  // namespace iilfm::detail
