// A simulated scan of an ArUco print, projected the way ARCHITECTURE.md prescribes, decodes with
// OpenCV's ArUco detector to the right id with the corners where the ground truth says: the print
// is neither mirrored nor rotated, and OpenCV's corner order is the canonical one.
#include <gtest/gtest.h>

#include <opencv2/aruco.hpp>

#include "iilfm/sim/sim.hpp"
#include "scan_image.hpp"

namespace iilfm::sim {
namespace {

using testing::intensity_image;
using testing::Projection;

struct Decoded {
  int id = -1;
  std::vector<cv::Point2f> corners;  // OpenCV's order, pixel centres at integers
};

std::vector<Decoded> decode(std::vector<std::uint8_t>& pixels, int n,
                            cv::aruco::PREDEFINED_DICTIONARY_NAME dictionary) {
  const cv::Mat image(n, n, CV_8UC1, pixels.data());
  auto params = cv::aruco::DetectorParameters::create();
  params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
  cv::aruco::detectMarkers(image, cv::aruco::getPredefinedDictionary(dictionary), corners, ids,
                           params);
  std::vector<Decoded> out;
  for (std::size_t i = 0; i < ids.size(); ++i) out.push_back({ids[i], corners[i]});
  return out;
}

// Scans `scene` with 60 Mid-40 frames from 2 m and decodes the 0.1 deg image.
void expect_decodes_with_truth_corners(const Scene& scene, const Isometry3& T_world_lidar,
                                       cv::aruco::PREDEFINED_DICTIONARY_NAME dictionary) {
  SimOptions o;
  o.T_world_lidar = T_world_lidar;
  o.frames = 60;
  const SimResult r = simulate(scene, mid40(), o);
  const Projection proj{0.1, 20};
  std::vector<std::uint8_t> image = intensity_image(r.cloud, proj);
  const std::vector<Decoded> found = decode(image, proj.size(), dictionary);
  ASSERT_EQ(found.size(), 1u);
  const MarkerTruth& truth = r.truth.markers[0];
  EXPECT_EQ(found[0].id, truth.id);
  for (int k = 0; k < 4; ++k) {
    const Vec2 expected = proj.pixel(truth.corners_lidar[k]) - Vec2(0.5, 0.5);
    const Vec2 got(found[0].corners[k].x, found[0].corners[k].y);
    EXPECT_LT((got - expected).norm(), 1.0)
        << "corner " << k << " at " << got.transpose() << ", truth at " << expected.transpose();
  }
}

// The paper's grid markers: 4x4 ArUco of 16 cm.
TEST(ArucoRoundTrip, PaperArucoDecodesWithTheTruthCorners) {
  SceneParams params;
  params.family = "aruco:DICT_4X4_50";
  params.id = 5;
  params.marker_size_m = 0.16;
  const SceneSetup setup = named_scene("tag-wall", params);
  ASSERT_EQ(setup.scene.markers[0].family, "aruco:DICT_4X4_50");
  expect_decodes_with_truth_corners(setup.scene, setup.T_world_lidar, cv::aruco::DICT_4X4_50);
}

// Turned in its plane, the corners still follow the print (not the image axes).
TEST(ArucoRoundTrip, TurnedOriginalArucoDecodesWithTheTruthCorners) {
  const Scene scene =
      wall_scene({wall_marker("aruco:DICT_ARUCO_ORIGINAL", 321, 0.2, 2, 0, 0, 120)}, 2, -1.5);
  expect_decodes_with_truth_corners(scene, Isometry3::Identity(), cv::aruco::DICT_ARUCO_ORIGINAL);
}

}  // namespace
}  // namespace iilfm::sim
