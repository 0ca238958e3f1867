// The result JSON never passes off a missing value as a number: unrecoverable corners are null,
// refused poses are null with the reason.
#include <gtest/gtest.h>

#include "iilfm/report.hpp"

namespace iilfm {
namespace {

FrameResult one_marker_with_a_lost_corner() {
  FrameResult r;
  MarkerResult m;
  m.detection.family = "apriltag:tag36h11";
  m.detection.corners_px = {Vec2(1, 1), Vec2(5, 1), Vec2(5, 5), Vec2(1, 5)};
  for (int k = 0; k < 4; ++k) {
    LiftedCorner c;
    c.point = Vec3(2, 0.1 * k, 0.2);
    c.status = k == 2 ? CornerStatus::kUnrecoverable
                      : (k == 3 ? CornerStatus::kInterpolated : CornerStatus::kObserved);
    m.corners.push_back(c);
  }
  m.corners[2].point = Vec3::Zero();  // what a careless writer would print
  r.markers.push_back(m);
  return r;
}

TEST(ReportJson, UnrecoverableCornerIsNullNeverZeros) {
  const nlohmann::json j = result_to_json(one_marker_with_a_lost_corner(), InputInfo{});
  const auto& m = j["markers"][0];
  EXPECT_TRUE(m["corners_lidar"][2].is_null());
  EXPECT_EQ(m["corners_lidar"][0][0], 2.0);
  EXPECT_EQ(m["corner_status"][2], "unrecoverable");
  EXPECT_EQ(m["corner_status"][3], "interpolated");
  EXPECT_EQ(m["observed"], nlohmann::json({true, true, false, false}));
  EXPECT_TRUE(m["T_lidar_marker"].is_null());
  EXPECT_FALSE(m.contains("covariance"));
  EXPECT_FALSE(m.contains("plane"));  // no plane was fitted (paper lifting)
}

TEST(ReportJson, FittedPlaneIsReportedWithWhereItsNormalCameFrom) {
  FrameResult r = one_marker_with_a_lost_corner();
  Plane p;
  p.normal = Vec3(-1, 0, 0);
  p.d = -2.0;
  p.inliers = 1234;
  p.rms = 0.0042;
  p.surround_scale = 3;
  p.ok = true;
  r.markers[0].plane = p;
  const nlohmann::json plane = result_to_json(r, InputInfo{})["markers"][0]["plane"];
  EXPECT_EQ(plane["normal"], nlohmann::json({-1.0, 0.0, 0.0}));
  EXPECT_EQ(plane["d_m"], -2.0);
  EXPECT_EQ(plane["points"], 1234);
  EXPECT_EQ(plane["rms_m"], 0.0042);
  EXPECT_EQ(plane["surround_scale"], 3.0);
  r.markers[0].plane->ok = false;  // a failed fit is not reported as a plane
  EXPECT_FALSE(result_to_json(r, InputInfo{})["markers"][0].contains("plane"));
}

TEST(ReportJson, RefusedPoseIsNullWithTheReason) {
  FrameResult r = one_marker_with_a_lost_corner();
  r.pose_missing_reason = "only 3 mapped corners could be lifted to 3-D (need 4)";
  r.pose_rejected = true;
  nlohmann::json j = result_to_json(r, InputInfo{});
  EXPECT_TRUE(j["pose"].is_null());
  EXPECT_EQ(j["pose_rejected"]["reason"], r.pose_missing_reason);
  EXPECT_EQ(j["pose_missing_reason"], r.pose_missing_reason);
  r.pose_rejected = false;  // nothing to refuse (no map): no pose_rejected
  j = result_to_json(r, InputInfo{});
  EXPECT_FALSE(j.contains("pose_rejected"));
}

}  // namespace
}  // namespace iilfm
