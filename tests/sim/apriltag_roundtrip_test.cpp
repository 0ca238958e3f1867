// The simulated scan, projected the way ARCHITECTURE.md prescribes (u = u0 - azimuth/res, v = v0 -
// elevation/res), decodes with libapriltag to the right id with the corners where the ground
// truth says: the print is neither mirrored nor rotated, and the corner order matches.
#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag36h11.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "iilfm/sim/sim.hpp"
#include "scan_image.hpp"

namespace iilfm::sim {
namespace {

using testing::intensity_image;
using testing::kRadToDeg;
using testing::Projection;

struct Detection {
  int id;
  std::array<Vec2, 4> corners;  // libapriltag order
};

std::vector<Detection> detect(std::vector<std::uint8_t>& pixels, int n, apriltag_family_t* family) {
  apriltag_detector_t* detector = apriltag_detector_create();
  apriltag_detector_add_family(detector, family);
  detector->quad_decimate = 1;
  detector->nthreads = 1;
  image_u8_t image = {n, n, n, pixels.data()};
  zarray_t* found = apriltag_detector_detect(detector, &image);
  std::vector<Detection> detections;
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* d;
    zarray_get(found, i, &d);
    Detection out{d->id, {}};
    for (int k = 0; k < 4; ++k) out.corners[k] = Vec2(d->p[k][0], d->p[k][1]);
    detections.push_back(out);
  }
  apriltag_detections_destroy(found);
  apriltag_detector_destroy(detector);
  return detections;
}

// libapriltag reports p[0..3] = bottom-left, bottom-right, top-right, top-left of the canonical
// image; the ground truth is top-left, top-right, bottom-right, bottom-left.
void expect_corners_match(const Detection& d, const MarkerTruth& truth, const Projection& proj,
                          double tolerance_px) {
  const int truth_of_detected[4] = {3, 2, 1, 0};
  for (int k = 0; k < 4; ++k) {
    const Vec2 expected = proj.pixel(truth.corners_lidar[truth_of_detected[k]]);
    EXPECT_LT((d.corners[k] - expected).norm(), tolerance_px)
        << "apriltag corner " << k << " at " << d.corners[k].transpose() << ", truth at "
        << expected.transpose();
  }
}

TEST(AprilTagRoundTrip, PaperTagDecodesWithTheTruthCorners) {
  const SceneSetup setup = named_scene("tag-wall");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = 60;
  const SimResult r = simulate(setup.scene, mid40(), o);
  const Projection proj{0.1, 20};
  std::vector<std::uint8_t> image = intensity_image(r.cloud, proj);
  apriltag_family_t* family = tag36h11_create();
  const std::vector<Detection> found = detect(image, proj.size(), family);
  tag36h11_destroy(family);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 0);
  expect_corners_match(found[0], r.truth.markers[0], proj, 1.0);
}

TEST(AprilTagRoundTrip, TurnedTagAt10mDecodesFromNoddingUltraPuckSweeps) {
  // A spinning sensor's rings are too sparse for a decode from one scan; 40 sweeps with the
  // LiDAR nodding through the ring gaps (up to 1 deg at the tag) stand in for a dense view.
  const SceneSetup setup = named_scene("ccw10m");
  SimOptions o;
  o.range_sigma_m = 0;
  o.intensity_sigma = 0;
  PointCloud dense;
  for (int step = 0; step < 40; ++step) {
    o.T_world_lidar.linear() =
        Eigen::AngleAxisd((step / 40.0 - 0.5) * 1.2 / kRadToDeg, Vec3::UnitY()).toRotationMatrix();
    o.seed = step + 1;
    const SimResult r = simulate(setup.scene, ultra_puck(), o);
    for (std::size_t i = 0; i < r.cloud.size(); ++i) {
      const Vec3 p = o.T_world_lidar * r.cloud.point(i);  // back into the level frame
      dense.push_back(p.x(), p.y(), p.z(), r.cloud.intensity[i]);
    }
  }
  o.T_world_lidar = Isometry3::Identity();
  const GroundTruth truth = ground_truth(setup.scene, ultra_puck(), o);
  const Projection proj{0.1, 8};
  std::vector<std::uint8_t> image = intensity_image(dense, proj);
  apriltag_family_t* family = tag16h5_create();
  const std::vector<Detection> found = detect(image, proj.size(), family);
  tag16h5_destroy(family);
  ASSERT_GE(found.size(), 1u);
  const auto it =
      std::find_if(found.begin(), found.end(), [](const Detection& d) { return d.id == 0; });
  ASSERT_NE(it, found.end());
  expect_corners_match(*it, truth.markers[0], proj, 1.5);
}

}  // namespace
}  // namespace iilfm::sim
