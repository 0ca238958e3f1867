// PointView: the pipeline reads points of any layout in place, with the same result as the
// structure-of-arrays cloud.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "iilfm/io/cloud_io.hpp"
#include "iilfm/marker_map.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"

namespace iilfm {
namespace {

// Rows of x, y, z, intensity and `extra` padding floats, as an (N, 4 + extra) numpy array.
std::vector<float> interleaved(const PointCloud& cloud, int extra) {
  const std::size_t stride = 4 + extra;
  std::vector<float> rows(cloud.size() * stride, -7.f);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    rows[i * stride] = cloud.x[i];
    rows[i * stride + 1] = cloud.y[i];
    rows[i * stride + 2] = cloud.z[i];
    rows[i * stride + 3] = cloud.intensity[i];
  }
  return rows;
}

PointView row_view(const std::vector<float>& rows, std::size_t n) {
  const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(rows.size() / n);
  PointView v;
  v.x = {rows.data(), stride};
  v.y = {rows.data() + 1, stride};
  v.z = {rows.data() + 2, stride};
  v.intensity = {rows.data() + 3, stride};
  v.count = n;
  return v;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(PointView, ViewsACloudWithoutCopying) {
  PointCloud cloud;
  cloud.push_back(1, 2, 3, 4);
  cloud.push_back(5, 6, 7, 8);
  const PointView v(cloud);
  EXPECT_EQ(v.size(), 2u);
  EXPECT_EQ(v.x.data, cloud.x.data());
  EXPECT_EQ(v.intensity[1], 8.f);
  EXPECT_FALSE(v.has_ring());
  EXPECT_EQ(v.point(1), Vec3(5, 6, 7));
}

TEST(PointView, InterleavedRowsGiveTheSameFrameResultAsTheCloud) {
  const std::string dir = IILFM_SOURCE_DIR "/data/sample/";
  const io::LoadedCloud loaded = io::read_cloud(dir + "mid40_tag_wall.pcd");
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid40"), options);
  options.map = MarkerMap::load(dir + "mid40_tag_wall_map.yaml");

  Pipeline soa(options);
  const FrameResult& expected = soa.process(loaded.cloud);
  ASSERT_EQ(expected.markers.size(), 1u);
  ASSERT_TRUE(expected.pose.has_value());

  for (int extra : {0, 3}) {
    const std::vector<float> rows = interleaved(loaded.cloud, extra);
    Pipeline strided(options);
    const FrameResult& got = strided.process(row_view(rows, loaded.cloud.size()));
    EXPECT_TRUE(same(got.image.intensity, expected.image.intensity));
    EXPECT_TRUE(same(got.image.range, expected.image.range));
    EXPECT_TRUE(same(got.image.index, expected.image.index));
    ASSERT_EQ(got.markers.size(), 1u);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(got.markers[0].detection.corners_px[k],
                expected.markers[0].detection.corners_px[k]);
      EXPECT_EQ(got.markers[0].corners[k].point, expected.markers[0].corners[k].point);
    }
    ASSERT_TRUE(got.pose.has_value());
    EXPECT_TRUE(got.pose->T_world_lidar.matrix() == expected.pose->T_world_lidar.matrix());
  }
}

}  // namespace
}  // namespace iilfm
