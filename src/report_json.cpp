#include <cmath>
#include <cstdio>
#include <string>

#include "iilfm/marker_coverage.hpp"
#include "iilfm/pose.hpp"
#include "iilfm/pose_covariance.hpp"
#include "iilfm/report.hpp"

namespace iilfm {

namespace {

using nlohmann::json;

// Rounds for output: 0.1 mm / 1e-6 keeps files readable without losing real precision.
double round_to(double value, double step) { return std::round(value / step) * step; }

// Four significant digits.
std::string format_g(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

json matrix_json(const Isometry3& T) {
  json rows = json::array();
  const Mat4 M = T.matrix();
  for (int r = 0; r < 4; ++r) {
    json row = json::array();
    for (int c = 0; c < 4; ++c) row.push_back(round_to(M(r, c), 1e-9));
    rows.push_back(row);
  }
  return rows;
}

json vec_json(const Vec3& v, double step) {
  return json::array({round_to(v.x(), step), round_to(v.y(), step), round_to(v.z(), step)});
}

// A pose's uncertainty: the 6x6 covariance row-major (rx, ry, rz in rad, right perturbation in
// the pose's own frame; x, y, z in m) and the standard deviations it gives.
void add_uncertainty(json& out, const Isometry3& T, const Mat6& C) {
  json rows = json::array();
  for (int r = 0; r < 6; ++r) {
    json row = json::array();
    // Relative rounding: variances span 1e-12 (sub-mm) to 1e-2.
    for (int c = 0; c < 6; ++c) row.push_back(std::stod(format_g(C(r, c))));
    rows.push_back(row);
  }
  out["covariance"] = rows;
  out["std_xyz_m"] = vec_json(translation_std(C), 1e-7);
  out["std_rpy_deg"] = vec_json(rpy_std_deg(T, C), 1e-5);
}

json marker_json(const MarkerResult& m, const ProjectedImage& image) {
  json corners_px = json::array(), corners_lidar = json::array(), observed = json::array(),
       status = json::array();
  for (const Vec2& px : m.detection.corners_px)
    corners_px.push_back({round_to(px.x(), 1e-4), round_to(px.y(), 1e-4)});
  for (const LiftedCorner& c : m.corners) {
    // An unrecoverable corner is null: never a made-up point.
    corners_lidar.push_back(c.valid() ? vec_json(c.point, 1e-6) : json(nullptr));
    observed.push_back(c.status == CornerStatus::kObserved);
    status.push_back(to_string(c.status));
  }
  json out = {{"family", m.detection.family},
              {"id", m.detection.id},
              {"corners_px", corners_px},
              {"corners_lidar", corners_lidar},
              {"observed", observed},
              {"corner_status", status},
              {"hamming", m.detection.hamming},
              {"decision_margin", round_to(m.detection.decision_margin, 1e-3)},
              {"in_map", m.in_map},
              // Share of the marker's pixels that hold a point (before hole filling).
              {"coverage", round_to(marker_coverage(m.detection, image), 1e-3)}};
  if (m.plane && m.plane->ok) {
    // The fitted plane (plane lifting): normal . x = d_m in the LiDAR frame, and whether its
    // normal came from the wall around the marker (surround_scale > 1) or the marker alone.
    const Plane& p = *m.plane;
    out["plane"] = {{"normal", vec_json(p.normal, 1e-7)},
                    {"d_m", round_to(p.d, 1e-6)},
                    {"points", p.inliers},
                    {"rms_m", round_to(p.rms, 1e-6)},
                    {"surround_scale", p.surround_scale}};
  }
  if (m.lifted_square) {
    // The nearest square to the corners as lifted: the marker's measured size, and how far from
    // square the corners were.
    out["measured_size_m"] = round_to(m.lifted_square->side_m, 1e-6);
    out["square_rms_m"] = round_to(m.lifted_square->rms_m, 1e-6);
  }
  if (m.size_disagrees) out["size_disagrees"] = true;  // with the map's or --marker-size
  if (m.T_lidar_marker) {
    out["T_lidar_marker"] = matrix_json(*m.T_lidar_marker);
    out["marker_fit_rms_m"] = round_to(m.marker_fit_rms, 1e-6);
    add_uncertainty(out, *m.T_lidar_marker, m.T_lidar_marker_covariance);
    // A ring marker's code is the same at every turn: its pose's turn about the normal is a
    // convention, not a measurement.
    if (!m.turn_known) out["turn_about_normal_known"] = false;
  } else {
    out["T_lidar_marker"] = nullptr;
  }
  return out;
}

}  // namespace

json result_to_json(const FrameResult& result, const InputInfo& input) {
  const ImageGeometry& g = result.image.geometry;
  json out;
  out["input"] = {{"path", input.path},
                  {"points", input.stats.points_in_file},
                  {"valid_points", input.stats.valid_points},
                  {"skipped_non_finite", input.stats.non_finite},
                  {"skipped_zero", input.stats.zero}};
  out["image"] = {{"width", g.width},
                  {"height", g.height},
                  {"res_h_deg", round_to(g.res_h * 180 / M_PI, 1e-9)},
                  {"res_v_deg", round_to(g.res_v * 180 / M_PI, 1e-9)},
                  {"rows", result.image.row_source},
                  {"observed_pixels", cv::countNonZero(result.image.mask)},
                  {"threshold", round_to(result.preprocessed.threshold, 1e-3)}};
  if (!input.resolution_source.empty()) out["image"]["resolution"] = input.resolution_source;
  if (result.preprocessed.no_intensity) out["image"]["no_intensity"] = true;  // all 0
  if (result.preprocessed.replaced_threshold) {
    // The fixed threshold lay above every intensity: Otsu's was used instead.
    out["image"]["threshold_replaced"] = {
        {"given", round_to(*result.preprocessed.replaced_threshold, 1e-3)},
        {"max_intensity", round_to(result.preprocessed.max_intensity, 1e-6)}};
  }
  if (result.threshold_retry) {
    // The preset's threshold found no marker; the frame was thresholded at Otsu's or locally too.
    const FrameResult::ThresholdRetry& retry = *result.threshold_retry;
    nlohmann::json& json = out["image"]["threshold_retry"];
    json = {{"fixed", round_to(retry.fixed, 1e-3)},
            {"method", retry.local ? "local" : "otsu"},
            {"found", retry.found}};
    if (!retry.local) json["otsu"] = round_to(retry.otsu, 1e-3);
  }
  if (result.preprocessed.geometry.height != g.height) {
    out["image"]["detector_height"] = result.preprocessed.geometry.height;  // square pixels
  }
  json markers = json::array();
  for (const MarkerResult& m : result.markers) markers.push_back(marker_json(m, result.image));
  out["markers"] = markers;
  // --ids: markers found with other ids, left out of "markers" (absent when there were none).
  if (result.unknown_ids_dropped > 0) out["markers_not_reported"] = result.unknown_ids_dropped;
  // Detections whose lifted corners are no square: chance matches, dropped (absent when none).
  if (result.not_square_dropped > 0) out["detections_not_square"] = result.not_square_dropped;
  if (result.pose) {
    const LidarPose& p = *result.pose;
    const Eigen::Quaterniond q(p.T_world_lidar.linear());
    out["pose"] = {{"T_world_lidar", matrix_json(p.T_world_lidar)},
                   {"xyz", vec_json(p.T_world_lidar.translation(), 1e-6)},
                   {"quat_xyzw",
                    {round_to(q.x(), 1e-9), round_to(q.y(), 1e-9), round_to(q.z(), 1e-9),
                     round_to(q.w(), 1e-9)}},
                   {"rpy_deg", vec_json(rpy_deg(p.T_world_lidar.linear()), 1e-6)},
                   {"rms_m", round_to(p.rms, 1e-6)},
                   {"corners_used", p.corners_used},
                   {"markers_used", p.markers_used}};
    json rejected = json::array();
    for (const RejectedMarker& m : p.markers_rejected)
      rejected.push_back({{"marker", m.key}, {"residual_m", round_to(m.residual_m, 1e-6)}});
    out["pose"]["markers_rejected"] = rejected;
    add_uncertainty(out["pose"], p.T_world_lidar, p.covariance);
  } else {
    out["pose"] = nullptr;
    out["pose_missing_reason"] = result.pose_missing_reason;
    if (result.pose_rejected) out["pose_rejected"] = {{"reason", result.pose_missing_reason}};
  }
  const StageTimes& t = result.times_ms;
  out["timing_ms"] = {{"read", round_to(input.read_ms, 1e-3)},
                      {"project", round_to(t.project, 1e-3)},
                      {"preprocess", round_to(t.preprocess, 1e-3)},
                      {"detect", round_to(t.detect, 1e-3)},
                      {"lift", round_to(t.lift, 1e-3)},
                      {"pose", round_to(t.pose, 1e-3)},
                      {"total", round_to(input.read_ms + t.total(), 1e-3)}};
  return out;
}

}  // namespace iilfm
