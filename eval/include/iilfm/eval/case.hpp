// One evaluation case: a simulated scan of a named scene, run through the pipeline, scored
// against the simulator's ground truth.
#pragma once

#include <cstdint>
#include <string>

#include "iilfm/pipeline.hpp"
#include "iilfm/sim/sim.hpp"

namespace iilfm::eval {

// What to simulate. Empty / zero fields mean the scene's or sensor's default.
struct CaseSpec {
  std::string scene = "tag-wall";  // sim::named_scene name
  sim::SceneParams scene_params;
  std::string sensor;  // sim sensor model (and pipeline preset when one has that name)
  int frames = 0;      // 0: 40 for a rosette, 1 for a spinning sensor
  // LiDAR roll, pitch, yaw (degrees, extrinsic x-y-z) on top of the scene's own orientation, about
  // the LiDAR's position: Table 2's pitched and yawed set-ups.
  Vec3 lidar_rpy_deg = Vec3::Zero();
  // Turn the LiDAR, per seed, by a random yaw and pitch of up to +-jitter_px / 2 image pixels (the
  // pipeline's resolution for the sensor): where the scan's samples fall on a marker's edges then
  // changes from seed to seed, as it does between real set-ups. Without it every seed samples
  // the same sub-pixel phase, and the pixel grid's error repeats as one fixed bias (0: none).
  double jitter_px = 0;
  // Spinning sensors: fire each ring at its column's azimuth, not at the sensor's own offsets
  // (sim::SensorModel::ring_azimuth_offsets_deg), as the simulator did before it had them: for
  // comparisons, and for cases found in such scans.
  bool on_column_grid = false;
  // Noise and physics (T_world_lidar, frames and seed are filled in from the fields above).
  sim::SimOptions physics;
};

struct SimulatedCase {
  sim::SceneSetup setup;
  sim::SensorModel sensor;
  sim::SimResult scan;  // invalid (NaN or zero) points already dropped, as the file readers do
};

// The "tag-wall" scene: one marker of `marker_size_m` facing `sensor` from `distance_m`.
CaseSpec tag_wall_spec(const std::string& sensor, double distance_m, double marker_size_m);
// The "grid" scene: 7 x 5 markers of `family` (e.g. "aruco:DICT_4X4_50") `distance_m` from
// `sensor`.
CaseSpec grid_spec(const std::string& sensor, const std::string& family, double distance_m);

SimulatedCase simulate_case(const CaseSpec& spec, std::uint64_t seed);

// The marker map a user would write for the scene (world corners of every marker).
MarkerMap map_of(const sim::Scene& scene);

// Pipeline options for a simulated sensor: its preset's resolution and threshold when iilfm has a
// preset of that name, otherwise the model's own column step and closest ring spacing.
PipelineOptions pipeline_options_for(const SimulatedCase& c, LiftMethod lift);

// Scores of one frame against the truth.
struct CaseScore {
  int visible = 0;          // markers the truth marks visible
  int detected = 0;         // visible markers found with their own family and id
  int false_positives = 0;  // detections not on any marker (or a marker found twice)
  int wrong_ids = 0;        // detections on a marker but with another family or id
  int corners = 0;          // lifted corners of detected markers compared with the truth
  double corner_error_mean = 0, corner_error_max = 0;  // metres
  // Mean side length of the lifted corners (before any known-size fit) minus the true size:
  // the shrink or growth of the detected square, metres.
  double size_error_mean = 0;
  int marker_poses = 0;  // detected markers with T_lidar_marker
  double marker_position_error_mean = 0, marker_rotation_error_mean_deg = 0;
  // The claimed uncertainty against these errors: sigma = root of the covariance's trace (the RMS
  // error the covariance predicts, position in metres, rotation in degrees); NEES = the 6-dof
  // normalised error squared e^T C^-1 e, whose mean is 6 when the covariance is right.
  double marker_position_sigma_mean = 0, marker_rotation_sigma_mean_deg = 0;
  double marker_nees_mean = 0;
  bool pose = false;                                  // a LiDAR pose was estimated
  double position_error = 0, rotation_error_deg = 0;  // of T_world_lidar
  double position_sigma = 0, rotation_sigma_deg = 0, pose_nees = 0;
  double time_ms = 0;  // pipeline stages
};

CaseScore score_frame(const FrameResult& result, const sim::GroundTruth& truth);

// Pipeline options an evaluation may switch to measure their effect on the same scans.
struct PipelineTweaks {
  bool edge_refine = PipelineOptions{}.edge_refine;
  bool weight_corners = LidarPoseOptions{}.weight_corners;
  PoseRefine pose_refine = LidarPoseOptions{}.refine;
  bool ring_decode = PipelineOptions{}.ring_decode;
  bool ring_candidates = PipelineOptions{}.ring_candidates;
  bool search_regions = AprilTagOptions{}.search_regions;
  bool gray_decode = AprilTagOptions{}.decode_gray;
  bool column_offsets = ProjectionOptions{}.column_offsets;
};

// Runs the pipeline with `lift` (and `tweaks`) on the simulated scan and scores it.
CaseScore run_case(const SimulatedCase& c, LiftMethod lift, const PipelineTweaks& tweaks = {});

const char* lift_name(LiftMethod lift);

}  // namespace iilfm::eval
