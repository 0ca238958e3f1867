// One frame through every stage: projection, preprocessing, detection, lifting, pose. Pipeline only
// wires the stages and times them; each stage is usable on its own.
//
// Threads: one Pipeline per thread. process() reuses the pipeline's buffers (projector, detectors,
// result), so a Pipeline, a SphericalProjector, a MarkerDetector, a FrameWindow, a FrameSource and
// a BagReader each belong to one thread at a time. Pipelines in different threads share nothing
// mutable (the family, dictionary and sensor tables are immutable function statics), so any number
// run in parallel (tests/threads). Shareable read-only across threads: PipelineOptions, MarkerMap,
// SensorPreset, PointCloud and PointView (nobody writing them). A FrameResult is the owning
// Pipeline's until its next process() call.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "iilfm/detector.hpp"
#include "iilfm/lidar_pose.hpp"
#include "iilfm/lift.hpp"
#include "iilfm/marker_map.hpp"
#include "iilfm/preprocess.hpp"
#include "iilfm/projection.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/square_shape.hpp"
#include "iilfm/window_projection.hpp"

namespace iilfm {

namespace detail {
class RingDecoder;
class TaskThreads;
}  // namespace detail

enum class LiftMethod {
  kPlane,  // sub-pixel corner rays meet the robustly fitted marker plane (default)
  kPaper,  // the paper's rule: the corner pixel's range, or the angle-bisector interpolation
};

// Marker ids per family ("apriltag:tag36h11" -> {0, 3}).
using KnownIds = std::map<std::string, std::vector<int>>;

struct PipelineOptions {
  ProjectionOptions projection;
  PreprocessOptions preprocess;
  std::vector<std::string> families = {"apriltag:tag36h11"};
  DetectorOptions detector;
  LiftMethod lift = LiftMethod::kPlane;
  PlaneFitOptions plane_fit;
  LiftOptions lift_options;
  std::optional<double> marker_size;  // edge of the black square for markers not in the map
  std::optional<MarkerMap> map;       // enables the LiDAR pose
  LidarPoseOptions pose;
  // When a marker's size is known (map or marker_size), report the square of that size fitted to
  // its four lifted corners instead of the corners themselves.
  bool fit_known_size = true;
  // Pixels (along each edge's image normal) of the quantisation error the pixel grid leaves on a
  // square marker's edges, carried into its corners' covariance (edge_offset_covariance);
  // 1/sqrt(12), a uniform error over one pixel. 0 leaves it out.
  double edge_sigma_px = 0.2887;
  // Move each detected side to where the intensity crosses halfway between the marker's own
  // black and white levels (edge_refine.hpp) before lifting: removes the shrink or growth a
  // global threshold gives blurred (beam-footprint) edges.
  bool edge_refine = true;
  // Drop detections whose black square spans fewer projected rows or columns than this many per
  // cell: they were decoded from resampled or filled pixels (0 = keep all).
  double min_samples_per_cell = 1.0;
  // On images with one row per ring: read each AprilTag or ArUco detection's cells from the rings
  // that crossed them and decode them with unsampled cells as erasures (docs/pipeline.md,
  // "Ring-sample decoding"). A detection the samples contradict is dropped, one they decode to
  // another id is corrected, one they confirm is kept even below min_samples_per_cell.
  bool ring_decode = true;
  // With ring_decode: also decode, from the ring samples, dark squares no detector decoded (the
  // range beyond one ring per cell row, and the ring phases where the detectors miss). Costs
  // nothing without such a square, a few milliseconds a VLP-16 frame with one (docs/pipeline.md).
  bool ring_candidates = true;
  // Ids known to be in the scene, per family ({"apriltag:tag36h11", {0, 3}}), besides the map's,
  // which are always known. Ring-sample decoding reads a known id from fewer ring samples: its
  // chance-match bits count only the known codes (docs/pipeline.md). `--ids` sets it.
  KnownIds known_ids;
  // Report only markers whose id is known (known_ids or the map). `--ids` sets it.
  bool only_known_ids = false;
  // Threads lifting the markers of a frame (edge refinement, plane fit and pose, one marker per
  // thread at a time), used with several markers in a cloud of at least 32k points; a single
  // marker's plane fit gathers its points on them (PlaneFitOptions::threads). Same results for
  // any count. `--threads` sets it with the projection's and preprocessing's.
  int lift_threads = 1;
  // Threads running the families' detectors on a frame, one detector per thread at a time (with
  // several families: AprilTag and ArUco together take the longer one's time, not the sum), and
  // on ring rows the ring candidates' dark squares beside them. Same results for any count.
  // `--threads` sets it with the others.
  int detect_threads = 1;
  // When a preset's fixed threshold finds no marker and Otsu's threshold over the image lies more
  // than a quarter of the fixed one away from it, threshold the frame at Otsu's and detect once
  // more: a cloud whose print and paper both sit above (or below) the preset's value, such as
  // black ink that returns 60 on a 0..255 scale, shows no marker at the preset's threshold.
  // FrameResult::threshold_retry reports it. A threshold the user gives (set_threshold) is kept.
  bool retry_with_otsu = true;
  // When the fixed threshold finds no marker and Otsu's is no other choice (above), threshold the
  // frame locally (PreprocessOptions::local_threshold) and detect once more. The Livox presets set
  // it: their 0.28 deg vertical beam divergence averages a far marker's black cells into the white
  // ones, which a fixed threshold near the black level (40 against print at 10 and 120) turns
  // white, while the local mean splits them. Not the default for near markers: a window smaller
  // than a cell breaks large cells into specks for ArUco (docs/sensors.md, "Detection range").
  bool retry_with_local_threshold = false;
  // With the plane lift: drop a square marker whose four lifted corners lie farther from the
  // nearest square of any size (RMS, square_shape.hpp) than this share of its edge and than 1.5
  // footprints of the coarser pixel at its range (on ring rows: the widest ring gap it spans). A
  // printed square lifts to a square; a detector's chance match on speckle (tag16h5 matches about
  // one noise quad in 550) lifts to whatever quadrilateral the speckle drew. Measured: true markers
  // in the range walks at most 0.122 of the edge, chance matches 0.23 and more (docs/pipeline.md,
  // "Square check"). 0 keeps all.
  double max_square_error = 0.15;
};

struct MarkerResult {
  Detection detection;
  std::vector<LiftedCorner> corners;  // one per detection keypoint, same order
  // The corners as lifted, before the known-size square replaced them (empty when it did not):
  // the LiDAR pose is fitted to these, so its residual still measures the detection.
  std::vector<Vec3> lifted_points;
  // When the size is known and >= 3 corners lifted, or for a marker of one keypoint (a ring
  // marker's centre) its centre and fitted plane.
  std::optional<Isometry3> T_lidar_marker;
  // False for a marker whose code is the same at every turn (ring markers): T_lidar_marker's turn
  // about the face normal is then a convention (y as near the LiDAR's up as the face allows), not
  // a measurement, and its covariance says so (a turn uniform over the circle).
  bool turn_known = true;
  double marker_fit_rms = 0;  // residual of that fit, metres: how far from a square of that size
  // The nearest square of any size to the four corners as lifted (square markers whose four
  // corners lifted): its edge is the marker's measured size.
  std::optional<SquareShape> lifted_square;
  // The size is known (map or marker_size) and the measured one differs from it by more than a
  // tenth plus two footprints of the coarser pixel at the marker's range: the size given is
  // likely not the black square's edge (the whole tag with its white margin, the sheet).
  bool size_disagrees = false;
  // Covariance of T_lidar_marker, 6x6 (pose_covariance.hpp: marker-frame rotation, centre in the
  // LiDAR frame), and the joint covariance (3n x 3n) of the n lifted corners it was fitted to
  // (the valid ones, in order), which the LiDAR pose takes over.
  Mat6 T_lidar_marker_covariance = Mat6::Zero();
  Eigen::MatrixXd corner_covariance;
  std::optional<Plane> plane;  // the fitted marker plane (plane lifting)
  bool in_map = false;
};

struct StageTimes {
  double project = 0, preprocess = 0, detect = 0, lift = 0, pose = 0;
  double total() const { return project + preprocess + detect + lift + pose; }
};

struct FrameResult {
  ProjectedImage image;
  PreprocessedImage preprocessed;
  std::vector<MarkerResult> markers;
  std::optional<LidarPose> pose;
  std::string pose_missing_reason;  // why pose is empty (no map, no mapped marker, too few corners)
  // Mapped markers were found but their pose was refused (too few corners, residual over
  // max_rms_m, markers disagreeing): pose_missing_reason says why.
  bool pose_rejected = false;
  StageTimes times_ms;
  // PipelineOptions::retry_with_otsu: the fixed threshold that found nothing, Otsu's threshold,
  // and the markers found at Otsu's (then `preprocessed.detect` and `.threshold` are Otsu's).
  // PipelineOptions::retry_with_local_threshold: `local` set, `otsu` unused, and the markers found
  // with the local threshold (then `preprocessed.detect` is its image).
  struct ThresholdRetry {
    double fixed = 0, otsu = 0;
    std::size_t found = 0;
    bool local = false;
  };
  std::optional<ThresholdRetry> threshold_retry;
  // PipelineOptions::only_known_ids: markers found whose ids were not known, so not reported.
  std::size_t unknown_ids_dropped = 0;
  // PipelineOptions::max_square_error: detections dropped because their lifted corners are no
  // square, in the pass reported (the threshold retry's when one ran).
  std::size_t not_square_dropped = 0;
};

// PipelineOptions::known_ids and the map's ids, per family, sorted and each once; InputError for
// an id outside its family.
KnownIds known_ids_of(const PipelineOptions& options);

// Drops the detections whose ids `known` does not hold; returns how many.
std::size_t drop_unknown_ids(const KnownIds& known, std::vector<Detection>& detections);

// The edge a marker is given: the map's when the map holds it, else options.marker_size.
std::optional<double> given_size(const PipelineOptions& options, const Detection& detection);

// Sets the preset's image resolution, field of view, naive threshold and intensity normalisation.
void apply_sensor_preset(const SensorPreset& preset, PipelineOptions& options);

// Every thread count of `options`: the projection's, the preprocessing's and the lift's (which a
// single marker's plane fit takes over). What `--threads N` and Python `threads=` set.
void set_threads(PipelineOptions& options, int threads);

class Pipeline {
 public:
  explicit Pipeline(PipelineOptions options);  // InputError for bad options or unknown families
  ~Pipeline();
  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;

  // Runs every stage on `cloud`. The returned reference stays valid until the next call.
  const FrameResult& process(const PointCloud& cloud);
  // The same over points in any layout, read in place; they must outlive the returned result's
  // use (its pixel->point index refers to them).
  const FrameResult& process(const PointView& points);
  // The union of a sliding window of frames. With a fixed field of view (the Livox presets) the
  // projection is updated incrementally from push to push (include/iilfm/window_projection.hpp);
  // otherwise the union is projected as a whole. The window must not change while the result is
  // used.
  const FrameResult& process(const FrameWindow& window);

  const PipelineOptions& options() const { return options_; }

 private:
  PipelineOptions options_;
  // Every stage after the projection, on the image in result_.
  const FrameResult& process_projected(const PointView& cloud, double project_ms);
  // Every detector, the ring checks and candidates, one report per marker, in a fixed order: the
  // detections in `images` (a binary image of result_.preprocessed), in the projected image's
  // pixels.
  std::vector<Detection> detect_markers(const DetectorImages& images, FrameResult& r);
  // Appends every family's detections in `images`, in the families' order, and runs `beside`
  // (when given) too: on up to options_.detect_threads threads, one task per thread at a time.
  void run_detectors(const DetectorImages& images, std::vector<Detection>& out,
                     const std::function<void()>& beside);
  // Whether this frame's threshold is a fixed one that either retry may replace: binarised with
  // it, not replaced by Otsu's above every intensity, and the cloud carries intensity.
  bool fixed_threshold_may_be_retried(const PreprocessedImage& image) const;
  // Otsu's threshold when PipelineOptions::retry_with_otsu applies to this frame's fixed one.
  std::optional<double> otsu_retry_threshold(const PreprocessedImage& image) const;
  // Drops undersampled detections and, on ring rows, those the ring samples contradict.
  void keep_measured_detections(std::vector<Detection>& detections, const FrameResult& r) const;
  // Refines, lifts and poses one detection (its plane fit's points gathered on `fit_threads`;
  // its sides refined on `edge_image`, `image` with its values at the pixel centres); lifts all of
  // them into r.markers, on up to options_.lift_threads threads.
  MarkerResult lift_marker(Detection detection, const PointView& cloud, const ProjectedImage& image,
                           const ProjectedImage& edge_image, int fit_threads) const;
  void lift_markers(std::vector<Detection>& detections, const PointView& cloud, FrameResult& r);
  // Whether a lifted square marker is too far from a square (PipelineOptions::max_square_error).
  bool not_square(const MarkerResult& marker, const ImageGeometry& geometry) const;
  // The intensity the thresholds work in: normalised when normalisation is on.
  const cv::Mat& ring_intensity(const FrameResult& r) const;

  SphericalProjector projector_;
  std::unique_ptr<WindowProjector> window_projector_;  // made on the first window
  std::vector<std::unique_ptr<MarkerDetector>> detectors_;
  std::unique_ptr<detail::RingDecoder> ring_decoder_;    // from the first ring-row image
  std::unique_ptr<detail::TaskThreads> detect_helpers_;  // from the first frame that uses them
  KnownIds known_ids_;                                   // known_ids_of(options_)
  FrameResult result_;
  cv::Mat retry_detect_;  // the binary image of a threshold retry (Otsu's or local), reused
  // The projected image with its values moved to the pixel centres, for edge refinement on ring
  // rows off the column grid (detail::intensity_at_centres), reused.
  ProjectedImage edge_image_;
};

}  // namespace iilfm
