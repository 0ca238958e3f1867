// Fuzz target: the whole pipeline (projection, preprocessing, AprilTag and ArUco detection,
// lifting, pose) on an arbitrary cloud. The first byte picks the row layout, collision policy and
// lifting method; the rest is read as float32 quadruples x y z intensity, NaN and Inf included.
// Images are kept small (1 degree pixels, at most 200 000 of them) so each run takes milliseconds;
// InputError (e.g. an image over that limit) is the one accepted failure.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "iilfm/error.hpp"
#include "iilfm/pipeline.hpp"

namespace {

iilfm::PipelineOptions options_for(std::uint8_t choice) {
  iilfm::PipelineOptions options;
  options.projection.res_h_deg = options.projection.res_v_deg = 1.0;
  options.projection.max_pixels = 200'000;
  options.projection.rows = (choice & 1) ? iilfm::RowLayout::kRings : iilfm::RowLayout::kUniform;
  options.projection.collision =
      (choice & 2) ? iilfm::CollisionPolicy::kNearest : iilfm::CollisionPolicy::kMean;
  options.lift = (choice & 4) ? iilfm::LiftMethod::kPaper : iilfm::LiftMethod::kPlane;
  options.families = {"apriltag:tag36h11", "aruco:DICT_4X4_50"};
  options.marker_size = 0.2;
  iilfm::MarkerMap map;
  iilfm::MapMarker marker;
  marker.family = "apriltag:tag36h11";
  marker.corners_world = {iilfm::Vec3(3, 0.1, 0.1), iilfm::Vec3(3, -0.1, 0.1),
                          iilfm::Vec3(3, -0.1, -0.1), iilfm::Vec3(3, 0.1, -0.1)};
  map.add(marker);
  options.map = map;
  return options;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static std::array<std::unique_ptr<iilfm::Pipeline>, 8> pipelines;
  const std::uint8_t choice = data[0] & 7;
  if (!pipelines[choice])
    pipelines[choice] = std::make_unique<iilfm::Pipeline>(options_for(choice));

  iilfm::PointCloud cloud;
  const std::size_t points = (size - 1) / 16;
  cloud.reserve(points);
  for (std::size_t i = 0; i < points; ++i) {
    float v[4];
    std::memcpy(v, data + 1 + 16 * i, sizeof v);
    cloud.push_back(v[0], v[1], v[2], v[3]);
  }
  try {
    pipelines[choice]->process(cloud);
  } catch (const iilfm::InputError&) {
  }
  return 0;
}
