// Real recorded scans (../shared/data/real, see its SOURCES.md): read them, project them, and
// report no marker where none is printed. Skipped when the data is not beside the checkout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <vector>

#include "iilfm/eval/case.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"
#include "real_data.hpp"

namespace iilfm {
namespace {

namespace fs = std::filesystem;

using testing::pandar64_scans;
const fs::path kRealData = testing::real_data_dir();

PipelineOptions pandar64_options(std::vector<std::string> families) {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("pandar64"), options);
  options.families = std::move(families);
  return options;
}

// The calibration boards carry a checkerboard and high-contrast rings, no coded marker: every
// AprilTag family must stay silent on all 11 frames.
TEST(RealScans, Pandar64ScansReportNoMarker) {
  const auto scans = pandar64_scans();
  if (scans.empty()) GTEST_SKIP() << "no real data at " << kRealData;
  Pipeline pipeline(pandar64_options({"apriltag:tag36h11", "apriltag:tag25h9", "apriltag:tag16h5",
                                      "apriltag:tagStandard41h12", "apriltag:tagCircle21h7"}));
  for (const fs::path& scan : scans) {
    const io::LoadedCloud loaded = io::read_cloud(scan.string());
    ASSERT_GT(loaded.cloud.size(), 100000u) << scan;
    const FrameResult& r = pipeline.process(loaded.cloud);
    EXPECT_EQ(r.markers.size(), 0u) << scan;
    // A 360-degree scan at 0.2 deg: one turn of 1800 columns (its azimuths span the whole turn,
    // which once gave 1801 and the first column's direction twice); every point in the image.
    EXPECT_EQ(r.image.geometry.width, 1800) << scan;
    EXPECT_EQ(r.image.points_projected, loaded.cloud.size()) << scan;
    EXPECT_GT(cv::countNonZero(r.image.mask), 60000) << scan;
    // Hesai's per-channel horizontal offsets put the rings' samples off the column grid.
    EXPECT_FALSE(r.image.column_offset.empty()) << scan;
  }
}

// The joint-calibration board faces the sensor 3.33 m ahead (SOURCES.md): its points must project
// into the image centre, not mirrored to the other side or upside down.
TEST(RealScans, Pandar64BoardProjectsStraightAhead) {
  const fs::path scan = kRealData / "opencalib_jointcalib_pandar64" / "2022-01-18-15-25-03-449.pcd";
  if (!fs::exists(scan)) GTEST_SKIP() << "no real data at " << scan;
  const io::LoadedCloud loaded = io::read_cloud(scan.string());
  ProjectedImage image;
  SphericalProjector(pandar64_options({}).projection).project(loaded.cloud, image);
  const ImageGeometry& g = image.geometry;
  // A point on the board, ahead and a little to the left (+y) and below the sensor.
  const Vec2 ahead = g.pixel_of_point(Vec3(3.33, 0.3, -0.2));
  EXPECT_NEAR(ahead.x(), (g.width - 1) / 2.0 - 0.3 / 3.33 * 180 / M_PI / 0.2, 2.0);
  const Vec2 higher = g.pixel_of_point(Vec3(3.33, 0.3, 0.3));
  EXPECT_LT(higher.y(), ahead.y());
  // Points at the board's distance really are there in the range image around that pixel.
  int near_board = 0;
  for (int dr = -3; dr <= 3; ++dr)
    for (int dc = -3; dc <= 3; ++dc) {
      const int r = static_cast<int>(std::lround(ahead.y())) + dr;
      const int c = static_cast<int>(std::lround(ahead.x())) + dc;
      if (g.contains_pixel(c, r) && image.observed(c, r) &&
          std::abs(image.range.at<float>(r, c) - 3.35) < 0.15)
        ++near_board;
    }
  EXPECT_GT(near_board, 5);
}

// Per ring (the cloud's ring field, 0 the lowest): the median elevation (deg) and where the
// samples lie in a 0.2 deg column (circular mean of the azimuth's fraction of a column).
struct RingLayout {
  std::vector<double> elevation_deg, place_in_column;
};

RingLayout ring_layout(const PointCloud& cloud, std::size_t rings) {
  std::vector<std::vector<double>> elevations(rings);
  std::vector<std::complex<double>> places(rings);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.ring[i] >= rings) continue;
    const double x = cloud.x[i], y = cloud.y[i], z = cloud.z[i];
    elevations[cloud.ring[i]].push_back(std::atan2(z, std::hypot(x, y)) * 180 / M_PI);
    const double column = std::atan2(y, x) * 180 / M_PI / 0.2;
    places[cloud.ring[i]] += std::polar(1.0, 2 * M_PI * (column - std::floor(column)));
  }
  RingLayout layout;
  for (std::size_t r = 0; r < rings; ++r) {
    std::vector<double>& e = elevations[r];
    if (e.empty()) return {};
    std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
    layout.elevation_deg.push_back(e[e.size() / 2]);
    const double turn = std::arg(places[r]) / (2 * M_PI);
    layout.place_in_column.push_back(turn - std::floor(turn));
  }
  return layout;
}

// The simulated Pandar64 (docs/simulator.md) lays out its rings as the real frames do: the same
// elevation within 0.01 deg and, ring by ring, the same place in a column relative to the lowest
// ring's within 0.01 column (where the columns start is the encoder's choice).
TEST(RealScans, SimulatedPandar64LaysOutItsRingsAsTheRealFrames) {
  const auto scans = pandar64_scans();
  if (scans.empty()) GTEST_SKIP() << "no real data at " << kRealData;
  const RingLayout real = ring_layout(io::read_cloud(scans.front().string()).cloud, 64);
  const eval::SimulatedCase c = eval::simulate_case(eval::tag_wall_spec("pandar64", 3.0, 1.0), 1);
  ASSERT_TRUE(c.scan.cloud.has_ring());
  const RingLayout simulated = ring_layout(c.scan.cloud, 64);
  ASSERT_EQ(real.elevation_deg.size(), 64u);
  ASSERT_EQ(simulated.elevation_deg.size(), 64u);
  for (std::size_t r = 0; r < 64; ++r) {
    EXPECT_NEAR(simulated.elevation_deg[r], real.elevation_deg[r], 0.01) << "ring " << r;
    const double relative = (simulated.place_in_column[r] - simulated.place_in_column[0]) -
                            (real.place_in_column[r] - real.place_in_column[0]);
    EXPECT_LT(std::abs(relative - std::round(relative)), 0.01) << "ring " << r;
  }
}

}  // namespace
}  // namespace iilfm
