#include "paper_baseline.hpp"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/range_image/range_image.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "iilfm/detector.hpp"

namespace iilfm::bench {

struct PaperBaseline::State {
  BaselineOptions options;
  pcl::PointCloud<pcl::PointXYZ> geometry, folded;
  pcl::RangeImage range_image, intensity_image;
  std::unique_ptr<MarkerDetector> detector;
  std::vector<Detection> found;
};

namespace {

// A heat colour map of values in [0, 1] (black, red, yellow, white: monotone in brightness), as a
// viewer paints a float image; the gray conversion of it is what the detector sees.
cv::Vec3b heat(float t) {
  const float h = std::clamp(t, 0.0f, 1.0f) * 3.0f;
  const auto channel = [](float v) {
    return static_cast<std::uint8_t>(255 * std::clamp(v, 0.f, 1.f));
  };
  return {channel(h - 2), channel(h - 1), channel(h)};  // BGR
}

void create(pcl::RangeImage& image, const pcl::PointCloud<pcl::PointXYZ>& cloud,
            const BaselineOptions& options) {
  image.createFromPointCloud(
      cloud, pcl::deg2rad(options.res_h_deg), pcl::deg2rad(options.res_v_deg),
      pcl::deg2rad(options.max_angle_width_deg), pcl::deg2rad(options.max_angle_height_deg),
      Eigen::Affine3f::Identity(), pcl::RangeImage::LASER_FRAME, 0.0f, 0.0f, 0);
}

}  // namespace

PaperBaseline::PaperBaseline(BaselineOptions options) : state_(std::make_unique<State>()) {
  state_->options = std::move(options);
  state_->detector = make_detector("apriltag:" + state_->options.family, DetectorOptions{});
}

PaperBaseline::~PaperBaseline() = default;

int PaperBaseline::detect(const PointCloud& cloud) {
  State& s = *state_;
  const std::size_t n = cloud.size();
  float max_intensity = 1e-6f;
  for (float i : cloud.intensity) max_intensity = std::max(max_intensity, i);
  // The geometry cloud, and the same directions with the (normalised) intensity as their range.
  s.geometry.resize(n);
  s.folded.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float x = cloud.x[i], y = cloud.y[i], z = cloud.z[i];
    s.geometry[i] = pcl::PointXYZ(x, y, z);
    const float range = std::sqrt(x * x + y * y + z * z);
    const float scale = range > 0 ? (cloud.intensity[i] / max_intensity + 1e-3f) / range : 0.0f;
    s.folded[i] = pcl::PointXYZ(x * scale, y * scale, z * scale);
  }
  create(s.range_image, s.geometry, s.options);
  create(s.intensity_image, s.folded, s.options);

  // Colour map, then gray, then the naive threshold.
  const int w = static_cast<int>(s.intensity_image.width);
  const int h = static_cast<int>(s.intensity_image.height);
  cv::Mat colour(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int r = 0; r < h; ++r) {
    cv::Vec3b* row = colour.ptr<cv::Vec3b>(r);
    for (int c = 0; c < w; ++c) {
      const float v = s.intensity_image.getPoint(c, r).range;
      if (std::isfinite(v) && v > 0) row[c] = heat(v);
    }
  }
  cv::Mat gray, binary;
  cv::cvtColor(colour, gray, cv::COLOR_BGR2GRAY);
  const cv::Vec3b level = heat(s.options.threshold / max_intensity);
  const double gray_threshold = 0.114 * level[0] + 0.587 * level[1] + 0.299 * level[2];
  cv::threshold(gray, binary, gray_threshold, 255, cv::THRESH_BINARY);
  s.found.clear();
  s.detector->detect(binary, s.found);
  return static_cast<int>(s.found.size());
}

}  // namespace iilfm::bench
