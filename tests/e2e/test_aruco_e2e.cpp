// The ArUco back-end end to end: a simulated plane carrying a drawMarker print through the whole
// pipeline, and the real Pandar64 scans (../shared/data/real) with every dictionary enabled.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/aruco.hpp>

#include "iilfm/io/cloud_io.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"
#include "real_data.hpp"

namespace iilfm {
namespace {

namespace fs = std::filesystem;

constexpr double kDeg = M_PI / 180.0;

std::vector<std::string> aruco_families() {
  std::vector<std::string> names;
  for (const std::string& f : known_families())
    if (f.rfind("aruco:", 0) == 0) names.push_back(f);
  return names;
}

// A printed DICT_4X4_50 sheet (black square `size` m, one-cell white margin) on a tilted,
// in-plane rotated plane about 3 m ahead, sampled like a LiDAR: 3x3 points per pixel of a 0.2 deg
// image, intensity 10 on black and 120 on white (the wall around the sheet is white too).
struct MarkerPlaneScene {
  static constexpr int kId = 23;
  static constexpr double kSize = 0.36;  // 6 cells of 6 cm: about 6 px per cell at 3 m
  Vec3 centre = Vec3(3.0, 0.15, -0.1);
  Vec3 x_axis, y_axis, normal;  // marker frame: right, up, out of the face towards the LiDAR
  cv::Mat print;                // drawMarker image incl. margin, 16 px per cell
  std::vector<Vec3> corners;    // TL, TR, BR, BL of the black square, LiDAR frame
  PointCloud cloud;

  MarkerPlaneScene() {
    // Facing the LiDAR (right = -y, up = +z), then turned 25 deg about the vertical, tilted back
    // 10 deg and rotated 20 deg in its own plane.
    const Mat3 facing = (Mat3() << 0, 0, -1, -1, 0, 0, 0, 1, 0).finished();
    const Mat3 R = Eigen::AngleAxisd(25 * kDeg, Vec3::UnitZ()).toRotationMatrix() *
                   Eigen::AngleAxisd(10 * kDeg, Vec3::UnitY()).toRotationMatrix() * facing *
                   Eigen::AngleAxisd(20 * kDeg, Vec3::UnitZ()).toRotationMatrix();
    x_axis = R.col(0);
    y_axis = R.col(1);
    normal = R.col(2);
    const auto dict = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50);
    cv::Mat marker;
    dict->drawMarker(kId, 6 * 16, marker, 1);
    cv::copyMakeBorder(marker, print, 16, 16, 16, 16, cv::BORDER_CONSTANT, 255);
    const double h = kSize / 2;
    corners = {centre - h * x_axis + h * y_axis, centre + h * x_axis + h * y_axis,
               centre + h * x_axis - h * y_axis, centre - h * x_axis - h * y_axis};

    const ImageGeometry g = geometry();
    for (int r = 0; r < g.height; ++r)
      for (int c = 0; c < g.width; ++c)
        for (double dv : {-1.0 / 3, 0.0, 1.0 / 3})
          for (double du : {-1.0 / 3, 0.0, 1.0 / 3}) {
            const Vec3 ray = g.ray(c + du, r + dv);
            const Vec3 p = ray * (normal.dot(centre) / normal.dot(ray));
            cloud.push_back(p.x(), p.y(), p.z(), intensity_at(p));
          }
  }

  static ImageGeometry geometry() {
    return geometry_for_bounds({-12 * kDeg, 18 * kDeg, -12 * kDeg, 10 * kDeg}, 0.2 * kDeg,
                               0.2 * kDeg);
  }

  float intensity_at(const Vec3& p) const {
    // Print coordinates: the black square spans [-kSize/2, kSize/2] in both axes.
    const double a = (p - centre).dot(x_axis), b = (p - centre).dot(y_axis);
    const double half_print = kSize / 2 * 8.0 / 6.0;
    const double col = (a / (2 * half_print) + 0.5) * print.cols;
    const double row = (0.5 - b / (2 * half_print)) * print.rows;
    if (col < 0 || row < 0 || col >= print.cols || row >= print.rows) return 120;
    return print.at<std::uint8_t>(static_cast<int>(row), static_cast<int>(col)) < 128 ? 10 : 120;
  }
};

TEST(ArucoPipeline, FindsTheMarkerOnASimulatedPlaneWithCornersWithinMillimetres) {
  const MarkerPlaneScene scene;
  PipelineOptions options;
  options.projection.res_h_deg = options.projection.res_v_deg = 0.2;
  options.preprocess.threshold = 65;
  options.families = {"aruco:DICT_4X4_50"};
  options.marker_size = MarkerPlaneScene::kSize;
  Pipeline pipeline(options);
  const FrameResult& r = pipeline.process(scene.cloud);
  ASSERT_EQ(r.markers.size(), 1u);
  const MarkerResult& m = r.markers[0];
  EXPECT_EQ(m.detection.family, "aruco:DICT_4X4_50");
  EXPECT_EQ(m.detection.id, MarkerPlaneScene::kId);
  ASSERT_EQ(m.corners.size(), 4u);
  double worst = 0, mean = 0;
  for (int k = 0; k < 4; ++k) {
    ASSERT_TRUE(m.corners[k].valid());
    const double err = (m.corners[k].point - scene.corners[k]).norm();
    worst = std::max(worst, err);
    mean += err / 4;
  }
  // A pixel is 10.5 mm at 3 m; measured: mean 0.75 mm, worst 1.1 mm (noise-free ranges).
  EXPECT_LT(mean, 0.002);
  EXPECT_LT(worst, 0.003);
  ASSERT_TRUE(m.T_lidar_marker.has_value());
  EXPECT_LT((m.T_lidar_marker->translation() - scene.centre).norm(), 0.001);  // measured 0.23 mm
  EXPECT_GT(m.T_lidar_marker->linear().col(2).dot(scene.normal), std::cos(0.5 * kDeg));
}

using testing::pandar64_scans;
const fs::path kRealData = testing::real_data_dir();

std::size_t markers_on_real_scans(const ArucoOptions& aruco, bool binarize,
                                  double min_samples_per_cell = 1.0) {
  PipelineOptions options;
  options.min_samples_per_cell = min_samples_per_cell;
  apply_sensor_preset(find_sensor_preset("pandar64"), options);
  options.preprocess.binarize = binarize;
  options.families = aruco_families();
  options.detector.aruco = aruco;
  Pipeline pipeline(options);
  std::size_t found = 0;
  for (const fs::path& scan : pandar64_scans())
    found += pipeline.process(io::read_cloud(scan.string()).cloud).markers.size();
  return found;
}

// SOURCES.md: unrestricted 4x4 and original ArUco dictionaries return slivers and look-alikes on
// these scans (no coded marker is printed). With the filter every dictionary stays silent.
TEST(ArucoRealScans, Pandar64ScansReportNoMarkerWithEveryDictionary) {
  if (pandar64_scans().empty()) GTEST_SKIP() << "no real data at " << kRealData;
  EXPECT_EQ(markers_on_real_scans({}, true), 0u);
  EXPECT_EQ(markers_on_real_scans({}, false), 0u);  // --gray
  // Without the filters the look-alikes are there, so the test above is not silent by accident.
  // Measured: 114 look-alikes unfiltered; the ArUco plausibility filter alone and the pipeline's
  // rule that a marker spans at least one ring per cell alone each leave none.
  ArucoOptions unfiltered;
  unfiltered.min_cell_px = 0;
  unfiltered.max_side_ratio = 1e9;
  unfiltered.min_quiet_zone = 0;
  EXPECT_GE(markers_on_real_scans(unfiltered, true, 0.0), 10u);
}

}  // namespace
}  // namespace iilfm
