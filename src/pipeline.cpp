#include "iilfm/pipeline.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <climits>
#include <cmath>
#include <exception>
#include <functional>

#include "convex_polygon.hpp"
#include "iilfm/duplicates.hpp"
#include "iilfm/edge_refine.hpp"
#include "iilfm/error.hpp"
#include "iilfm/marker_coverage.hpp"
#include "iilfm/pose.hpp"
#include "iilfm/pose_covariance.hpp"
#include "iilfm/square_pixels.hpp"
#include "iilfm/square_shape.hpp"
#include "parallel_parts.hpp"
#include "ring_decoding.hpp"
#include "ring_row_alignment.hpp"
#include "seam_detection.hpp"
#include "task_threads.hpp"

namespace iilfm {

namespace {

class Stopwatch {
 public:
  double lap_ms() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// The finer side of a pixel, in metres, at `point`: the unit of the corners' in-plane prior.
double pixel_metres(const ImageGeometry& geometry, const Vec3& point) {
  return std::min(geometry.res_h, geometry.res_v) * point.norm();
}

// A marker of one keypoint (a ring marker, whose code is the same at every turn): its centre and
// the fitted plane's normal fix 5 of the 6 degrees of freedom. The marker's z is the normal
// towards the LiDAR, its y the LiDAR's up as seen in the face (its x where the face is level),
// and the covariance gives the turn about z the variance of a uniform turn.
void estimate_centre_pose(MarkerResult& marker, const ImageGeometry& geometry) {
  if (marker.corners.size() != 1 || !marker.corners[0].valid() || !marker.plane ||
      !marker.plane->ok)
    return;
  const Plane& plane = *marker.plane;
  const Vec3 centre = marker.corners[0].point;
  const Vec3 z = plane.normal.dot(centre) < 0 ? plane.normal : Vec3(-plane.normal);
  Vec3 up = Vec3::UnitZ() - z * z.z();
  if (up.norm() < 0.1) up = Vec3::UnitX() - z * z.x();
  const Vec3 y = up.normalized(), x = y.cross(z);
  Isometry3 T = Isometry3::Identity();
  T.linear() << x, y, z;
  T.translation() = centre;
  marker.T_lidar_marker = T;
  marker.turn_known = false;
  const double pixel_m = pixel_metres(geometry, centre);
  marker.corner_covariance = plane_corner_covariance({centre}, plane, 0.1 * pixel_m);
  // A slope b along the plane's axis a tilts the normal by -b a: a rotation of z x (-b a).
  Mat6 C = Mat6::Zero();
  for (int k = 0; k < 2; ++k) {
    const Vec3 axis = k == 0 ? plane.axis1 : plane.axis2;
    const Vec3 turn = T.linear().transpose() * z.cross(axis);
    C.topLeftCorner<3, 3>() += plane.slope_variance(k) * turn * turn.transpose();
  }
  C(2, 2) = M_PI * M_PI / 3;  // uniform over (-pi, pi]
  C.bottomRightCorner<3, 3>() = marker.corner_covariance;
  marker.T_lidar_marker_covariance = C;
}

// Pose of a square marker from its lifted corners, when its size is known. With `fit_square`
// and all four corners lifted, the corners are replaced by the least-squares square of that size
// in the fitted pose (their independent errors average out); the fit's RMS says how far the
// detection was from that square.
// The covariance of the fitted pose comes from the plane fit's uncertainty and the in-plane
// scatter of the corners about the best affine image of the square (a shrink moves no pose), with
// a prior of a tenth of a pixel, plus the pixel grid's error on the square's edges
// (edge_offset_covariance); without a plane, from the residual alone. A marker of one keypoint
// goes to estimate_centre_pose.
void estimate_marker_pose(MarkerResult& marker, double size, bool fit_square,
                          const ProjectedImage& image, double edge_sigma_px) {
  const ImageGeometry& geometry = image.geometry;
  const std::vector<Vec3> model = marker_frame_keypoints(marker.detection, size);
  if (model.size() == 1) return estimate_centre_pose(marker, geometry);
  std::vector<Vec3> source, target;
  for (std::size_t k = 0; k < marker.corners.size() && k < model.size(); ++k) {
    if (!marker.corners[k].valid()) continue;
    source.push_back(model[k]);
    target.push_back(marker.corners[k].point);
  }
  const RigidFit fit = fit_rigid(source, target);
  if (!fit.ok) return;
  marker.T_lidar_marker = fit.T;
  marker.marker_fit_rms = fit.rms;
  if (marker.plane && marker.plane->ok) {
    const double pixel_m = pixel_metres(geometry, fit.T.translation());
    const double residual_sq = affine_residual_sq(source, target, fit.T);
    const double sigma = in_plane_sigma(residual_sq, target.size(), 0.1 * pixel_m);
    marker.corner_covariance = plane_corner_covariance(target, *marker.plane, sigma);
    if (edge_sigma_px > 0 && marker.detection.keypoints_marker.empty() &&
        source.size() == marker.detection.corners_px.size()) {
      // Each sample that falls at its own place within its pixel (integrated non-repetitive
      // scans, averaged per pixel) adds a phase to an edge; a spinning LiDAR's samples sit on the
      // same grid sweep after sweep.
      if (!geometry.ring_rows())
        edge_sigma_px /= std::sqrt(std::max(1.0, marker_points_per_pixel(marker.detection, image)));
      marker.corner_covariance +=
          edge_offset_covariance(source, marker.detection.corners_px, fit.T, edge_sigma_px);
    }
  } else {
    const double dof = std::max(1.0, 3.0 * static_cast<double>(target.size()) - 6);
    const double variance = fit.rms * fit.rms * static_cast<double>(target.size()) / dof;
    const auto n = static_cast<Eigen::Index>(3 * target.size());
    marker.corner_covariance = Eigen::MatrixXd::Identity(n, n) * variance;
  }
  marker.T_lidar_marker_covariance =
      rigid_fit_covariance(source, target, {}, marker.corner_covariance, false);
  if (fit_square && source.size() == 4 && marker.corners.size() == 4 &&
      marker.detection.keypoints_marker.empty()) {
    for (std::size_t k = 0; k < 4; ++k) {
      marker.lifted_points.push_back(marker.corners[k].point);
      marker.corners[k].point = fit.T * model[k];
    }
  }
}

// The world coordinates of a mapped marker's keypoints: the map's corners for a square marker,
// the keypoints placed by the marker's map pose for a board.
std::vector<Vec3> world_keypoints(const Detection& detection, const MapMarker& mapped) {
  if (detection.keypoints_marker.empty())
    return {mapped.corners_world.begin(), mapped.corners_world.end()};
  const auto square = marker_frame_corners(mapped.size);
  const RigidFit T_world_marker = fit_rigid(
      {square.begin(), square.end()}, {mapped.corners_world.begin(), mapped.corners_world.end()});
  std::vector<Vec3> world = marker_frame_keypoints(detection, mapped.size);
  for (Vec3& p : world) p = T_world_marker.T * p;
  return world;
}

// A marker whose black square spans fewer image rows or columns than it has cells was decoded
// from resampled or hole-filled pixels, not from measurements: a look-alike, not a marker. Codes
// that cannot correct a single bit (ArUco's original and 4x4_1000 dictionaries) need two rows per
// cell: with fewer, one misread cell gives another valid id (measured: a 40 cm ARUCO_ORIGINAL at
// 1 m on a VLP-16, 1.6 rings per cell, read as a wrong id in 5 of 5 scans).
bool undersampled(const Detection& d, double min_samples_per_cell) {
  if (min_samples_per_cell <= 0 || d.corners_px.size() < 3) return false;
  const FamilyLayout layout = family_layout(d.family);
  const int cells = layout.border_width;
  if (cells <= 0) return false;
  if (layout.min_distance > 0 && layout.min_distance < 3) min_samples_per_cell *= 2;
  double u_min = 1e18, u_max = -1e18, v_min = 1e18, v_max = -1e18;
  for (const Vec2& p : d.corners_px) {
    u_min = std::min(u_min, p.x());
    u_max = std::max(u_max, p.x());
    v_min = std::min(v_min, p.y());
    v_max = std::max(v_max, p.y());
  }
  const double needed = min_samples_per_cell * cells;
  return v_max - v_min + 1 < needed || u_max - u_min + 1 < needed;
}

// The nearest square to a square marker's four lifted corners; none for a board, a ring marker
// or a corner that did not lift.
std::optional<SquareShape> lifted_square_of(const MarkerResult& marker) {
  if (marker.corners.size() != 4 || !marker.detection.keypoints_marker.empty()) return std::nullopt;
  std::array<Vec3, 4> points;
  for (std::size_t k = 0; k < 4; ++k) {
    if (!marker.corners[k].valid()) return std::nullopt;
    points[k] = marker.corners[k].point;
  }
  return nearest_square(points);
}

// The footprint, at a lifted square marker's range, of the image's coarser pixel where the marker
// lies: about the detector's own corner error, which makes a marker a few pixels across measure
// less exactly. Ring rows are as far apart as the widest gap between the rings the marker spans
// (a VLP-32C's rings are 0.33 deg apart at the horizon and up to 9 deg below it).
double coarse_footprint(const ImageGeometry& geometry, const MarkerResult& marker) {
  double row = geometry.res_v;
  const std::vector<double>& rings = geometry.row_elevation;
  const std::vector<Vec2>& corners = marker.detection.corners_px;
  const std::optional<cv::Rect2d> box =
      rings.empty() ? std::nullopt : detail::box_around(corners.data(), corners.size());
  if (box && !corners.empty()) {
    const int last = static_cast<int>(rings.size()) - 1;
    const int top = std::clamp(static_cast<int>(std::floor(box->y)), 0, last);
    const int bottom = std::clamp(static_cast<int>(std::ceil(box->y + box->height)), 0, last);
    row = 0;
    for (int r = std::max(top, 1); r <= std::max(bottom, 1) && r <= last; ++r)
      row = std::max(row,
                     rings[static_cast<std::size_t>(r - 1)] - rings[static_cast<std::size_t>(r)]);
    if (!(row > 0)) row = geometry.res_v;
  }
  return std::max(geometry.res_h, row) * marker.lifted_square->centre.norm();
}

}  // namespace

std::optional<double> given_size(const PipelineOptions& options, const Detection& detection) {
  if (options.map)
    if (const MapMarker* mapped = options.map->find(detection.family, detection.id))
      return mapped->size;
  return options.marker_size;
}

void apply_sensor_preset(const SensorPreset& preset, PipelineOptions& options) {
  constexpr double kRad = M_PI / 180.0;
  options.projection.res_h_deg = preset.res_h_deg;
  options.projection.res_v_deg = preset.res_v_deg;
  options.projection.field_of_view =
      AngularBounds{preset.fov_h_min_deg * kRad, preset.fov_h_max_deg * kRad,
                    preset.fov_v_min_deg * kRad, preset.fov_v_max_deg * kRad};
  options.projection.rows =
      preset.kind == ScanKind::kSpinning ? RowLayout::kRings : RowLayout::kUniform;
  options.preprocess.threshold = preset.threshold;
  options.preprocess.normalise.mode = preset.normalise;
  options.retry_with_local_threshold = preset.retry_local_threshold;
}

void set_threads(PipelineOptions& options, int threads) {
  options.projection.threads = threads;
  options.preprocess.threads = threads;
  options.lift_threads = threads;
  options.detect_threads = threads;
}

Pipeline::Pipeline(PipelineOptions options)
    : options_(std::move(options)), projector_(options_.projection) {
  if (options_.families.empty()) throw InputError("no marker family given (use --marker)");
  if (options_.marker_size && !(*options_.marker_size > 0))
    throw InputError("--marker-size must be positive (metres)");
  for (const std::string& family : options_.families)
    detectors_.push_back(make_detector(family, options_.detector));
  known_ids_ = known_ids_of(options_);
}

KnownIds known_ids_of(const PipelineOptions& options) {
  KnownIds known = options.known_ids;
  if (options.map)
    for (const MapMarker& m : options.map->markers()) known[m.family].push_back(m.id);
  for (auto& [family, ids] : known) {
    const int count = family_layout(family).ids;
    for (int id : ids)
      if (id < 0 || (count > 0 && id >= count))
        throw InputError("marker id " + std::to_string(id) + " is not in " + family + " (ids 0.." +
                         std::to_string(count - 1) + ")");
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  }
  return known;
}

std::size_t drop_unknown_ids(const KnownIds& known, std::vector<Detection>& detections) {
  const auto unknown =
      std::remove_if(detections.begin(), detections.end(), [&](const Detection& d) {
        const auto ids = known.find(d.family);
        return ids == known.end() ||
               !std::binary_search(ids->second.begin(), ids->second.end(), d.id);
      });
  const auto dropped = static_cast<std::size_t>(detections.end() - unknown);
  detections.erase(unknown, detections.end());
  return dropped;
}

Pipeline::~Pipeline() = default;
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;

const FrameResult& Pipeline::process(const PointCloud& cloud) { return process(PointView(cloud)); }

const FrameResult& Pipeline::process(const PointView& cloud) {
  Stopwatch watch;
  projector_.project(cloud, result_.image);
  return process_projected(cloud, watch.lap_ms());
}

const FrameResult& Pipeline::process(const FrameWindow& window) {
  if (!WindowProjector::supports(options_.projection)) return process(window.view());
  Stopwatch watch;
  if (!window_projector_)
    window_projector_ = std::make_unique<WindowProjector>(options_.projection);
  window_projector_->project(window, result_.image);
  return process_projected(window.view(), watch.lap_ms());
}

const cv::Mat& Pipeline::ring_intensity(const FrameResult& r) const {
  return options_.preprocess.normalise.mode != IntensityNormalisation::kNone
             ? r.preprocessed.normalised
             : r.image.intensity;
}

void Pipeline::keep_measured_detections(std::vector<Detection>& detections,
                                        const FrameResult& r) const {
  const bool rings = ring_decoder_ && r.image.geometry.ring_rows();
  const cv::Mat& intensity = ring_intensity(r);
  std::size_t kept = 0;
  for (Detection& d : detections) {
    bool keep = !undersampled(d, options_.min_samples_per_cell);
    if (rings) {
      switch (ring_decoder_->verify(d, r.image, intensity)) {
        case detail::RingVerdict::kConfirmed:
        case detail::RingVerdict::kCorrected:
          keep = true;
          break;
        case detail::RingVerdict::kContradicted:
          keep = false;
          break;
        case detail::RingVerdict::kUndecided:
          break;
      }
    }
    if (!keep) continue;
    if (&detections[kept] != &d) detections[kept] = std::move(d);  // no self-move
    ++kept;
  }
  detections.resize(kept);
}

namespace {

// The pixels edge refinement may read around `detections`: each one's box grown by half its size
// (past the quiet zone, a cell wide, of any family) and 2 pixels; every column when a box has
// columns past the image's edges (across a full circle's seam they continue on the other side).
cv::Rect edge_reach(const std::vector<Detection>& detections, int width) {
  cv::Rect reach;
  for (const Detection& d : detections) {
    if (d.corners_px.empty()) continue;
    const std::optional<cv::Rect2d> corners =
        detail::box_around(d.corners_px.data(), d.corners_px.size());
    if (!corners) return cv::Rect(0, 0, INT_MAX / 2, INT_MAX / 2);  // everything
    const double grow = 0.5 * std::max(corners->width, corners->height) + 2;
    const int x0 = static_cast<int>(std::floor(corners->x - grow)),
              x1 = static_cast<int>(std::ceil(corners->x + corners->width + grow));
    const int y0 = static_cast<int>(std::floor(corners->y - grow)),
              y1 = static_cast<int>(std::ceil(corners->y + corners->height + grow));
    const cv::Rect box(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
    reach = reach.empty() ? box : (reach | box);
  }
  if (reach.x < 0 || reach.x + reach.width > width) {  // wrapped columns: every column
    reach.x = 0;
    reach.width = width;
  }
  return reach;
}

}  // namespace

MarkerResult Pipeline::lift_marker(Detection detection, const PointView& cloud,
                                   const ProjectedImage& image, const ProjectedImage& edge_image,
                                   int fit_threads) const {
  MarkerResult marker;
  if (options_.edge_refine) {
    const EdgeRefinement edges = refine_edges_to_mid_level(
        detection.corners_px, edge_image, family_layout(detection.family).border_width);
    if (edges.ok) detection.corners_px = edges.corners_px;
  }
  if (options_.lift == LiftMethod::kPlane) {
    PlaneFitOptions fit = options_.plane_fit;
    fit.threads = fit_threads;
    marker.plane = fit_marker_plane(keypoint_outline(detection), image, cloud, fit);
    for (const Vec2& px : detection.corners_px)
      marker.corners.push_back(lift_on_plane(px, image, *marker.plane));
  } else {
    for (const Vec2& px : detection.corners_px)
      marker.corners.push_back(lift_paper(px, image, options_.lift_options));
  }
  marker.detection = std::move(detection);
  marker.lifted_square = lifted_square_of(marker);
  marker.in_map =
      options_.map && options_.map->find(marker.detection.family, marker.detection.id) != nullptr;
  const std::optional<double> size = given_size(options_, marker.detection);
  if (size && marker.lifted_square) {
    // Measured: true sizes within 0.43 of this allowance on the range walks (docs/pipeline.md).
    const double allowance = 0.1 * *size + 2 * coarse_footprint(image.geometry, marker);
    marker.size_disagrees = std::abs(marker.lifted_square->side_m - *size) > allowance;
  }
  if (size)
    estimate_marker_pose(marker, *size, options_.fit_known_size, image, options_.edge_sigma_px);
  return marker;
}

void Pipeline::lift_markers(std::vector<Detection>& detections, const PointView& cloud,
                            FrameResult& r) {
  // Markers are lifted independently (the plane fit's buffers are per thread), each into its own
  // slot, so the results do not depend on the threads. A small cloud's lifts take less than a
  // thread's start.
  constexpr std::size_t kMinPointsForThreads = 32768;
  const std::size_t n = detections.size();
  r.markers.resize(n);
  const int parts =
      cloud.size() >= kMinPointsForThreads ? detail::parts_for(options_.lift_threads, n, 1) : 1;
  // Threads left over (a single marker) gather its plane fit's points.
  const int fit_threads = std::max(options_.plane_fit.threads, options_.lift_threads / parts);
  // Edges are measured where the samples lie: with samples off the column grid, on the values
  // moved to the pixel centres (the same image's headers otherwise).
  const bool centred = options_.edge_refine && n > 0 && !r.image.column_offset.empty();
  if (centred) {
    edge_image_.geometry = r.image.geometry;
    edge_image_.mask = r.image.mask;
    edge_image_.count = r.image.count;
    detail::intensity_at_centres(r.image, edge_image_.intensity,
                                 edge_reach(detections, r.image.geometry.width));
  }
  std::vector<std::exception_ptr> failures(static_cast<std::size_t>(parts));
  detail::in_parts(parts, [&](int k, int count) {
    const auto [begin, end] = detail::part_range(n, k, count);
    try {
      for (std::size_t i = begin; i < end; ++i)
        r.markers[i] = lift_marker(std::move(detections[i]), cloud, r.image,
                                   centred ? edge_image_ : r.image, fit_threads);
    } catch (...) {
      failures[static_cast<std::size_t>(k)] = std::current_exception();
    }
  });
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
  const auto no_square = [&](const MarkerResult& m) { return not_square(m, r.image.geometry); };
  const auto kept = std::remove_if(r.markers.begin(), r.markers.end(), no_square);
  r.not_square_dropped = static_cast<std::size_t>(r.markers.end() - kept);
  r.markers.erase(kept, r.markers.end());
}

bool Pipeline::not_square(const MarkerResult& marker, const ImageGeometry& geometry) const {
  // The paper's lift takes each corner's own range: a corner pixel on the wall behind distorts a
  // true marker's shape (measured 0.11 of the edge at 2 m on a Mid-40).
  if (options_.max_square_error <= 0 || options_.lift != LiftMethod::kPlane) return false;
  if (!marker.lifted_square) return false;
  // The corners' own error: a detector's corner within a pixel or so of the edge it saw.
  constexpr double kNoiseFootprints = 1.5;
  const SquareShape& square = *marker.lifted_square;
  return square.rms_m > options_.max_square_error * square.side_m &&
         square.rms_m > kNoiseFootprints * coarse_footprint(geometry, marker);
}

bool Pipeline::fixed_threshold_may_be_retried(const PreprocessedImage& image) const {
  const PreprocessOptions& p = options_.preprocess;
  return p.threshold && p.binarize && !p.local_threshold && !image.replaced_threshold &&
         !image.no_intensity;
}

std::optional<double> Pipeline::otsu_retry_threshold(const PreprocessedImage& image) const {
  if (!options_.retry_with_otsu || !fixed_threshold_may_be_retried(image)) return std::nullopt;
  // Closer than this share of the fixed threshold, Otsu's is the same choice (the real Pandar64
  // frames: 96 against the preset's 100).
  constexpr double kLeastGap = 0.25;
  const double otsu = otsu_threshold(image);
  if (std::abs(otsu - image.threshold) < kLeastGap * std::abs(image.threshold)) return std::nullopt;
  return otsu;
}

void Pipeline::run_detectors(const DetectorImages& images, std::vector<Detection>& out,
                             const std::function<void()>& beside) {
  const std::size_t tasks = detectors_.size() + (beside ? 1 : 0);
  const int parts = detail::parts_for(options_.detect_threads, tasks, 1);
  if (parts <= 1) {
    for (auto& detector : detectors_) detector->detect_images(images, out);
    if (beside) beside();
    return;
  }
  // Each thread takes the next task not yet run (their costs differ by family), and each
  // detector's markers go to its own list, joined in the families' order. The helper threads
  // stay for the next frame.
  std::vector<std::vector<Detection>> found(detectors_.size());
  std::vector<std::exception_ptr> failures(tasks);
  if (!detect_helpers_) {  // as many as a frame's tasks can use: the detectors and one beside
    const int most = detail::parts_for(options_.detect_threads, detectors_.size() + 1, 1);
    detect_helpers_ = std::make_unique<detail::TaskThreads>(most - 1);
  }
  detect_helpers_->run(tasks, [&](std::size_t i) {
    try {
      if (i < detectors_.size()) {
        detectors_[i]->detect_images(images, found[i]);
      } else {
        beside();
      }
    } catch (...) {
      failures[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
  for (std::vector<Detection>& list : found)
    for (Detection& d : list) out.push_back(std::move(d));
}

std::vector<Detection> Pipeline::detect_markers(const DetectorImages& images, FrameResult& r) {
  // The families' cell code books, built once the first image with ring rows arrives (tens of
  // milliseconds for tag36h11: a Livox user never pays it).
  const bool rings = r.image.geometry.ring_rows();
  if (options_.ring_decode && !ring_decoder_ && rings)
    ring_decoder_ = std::make_unique<detail::RingDecoder>(options_.families,
                                                          detail::RingDecodeSettings{}, known_ids_);
  const bool candidates = ring_decoder_ && options_.ring_candidates && rings;
  // The ring candidates' dark squares are found beside the detectors (on another thread when
  // there are threads to spare): they need only the binary image.
  detail::RingDecoder::Quads quads;
  const auto find_quads = [&] {
    quads = ring_decoder_->candidate_quads(images.image, r.preprocessed.geometry, r.image);
  };
  std::vector<Detection> detections;
  run_detectors(images, detections, candidates ? std::function<void()>(find_quads) : nullptr);
  detect_across_seam(images, r.preprocessed.geometry, detectors_, detections);
  // Corners from the detector's image (square pixels) to the projected image's coordinates.
  for (Detection& d : detections) {
    for (Vec2& px : d.corners_px) px = map_pixel(px, r.preprocessed.geometry, r.image.geometry);
    for (Vec2& px : d.outline_px) px = map_pixel(px, r.preprocessed.geometry, r.image.geometry);
    detail::move_to_samples(r.image, d.corners_px, d.outline_px);
  }
  keep_measured_detections(detections, r);
  if (candidates) {
    // Only where no detector reported a marker: a detection there was already checked.
    const auto covered = [&](const Vec2& centre) {
      return std::any_of(detections.begin(), detections.end(), [&](const Detection& d) {
        return detail::inside_convex(centre, d.corners_px);
      });
    };
    std::vector<Detection> decoded;
    ring_decoder_->decode_candidates(images.image, r.preprocessed.geometry, r.image,
                                     ring_intensity(r), quads, decoded, covered);
    for (Detection& d : decoded) detections.push_back(std::move(d));
  }
  r.unknown_ids_dropped = options_.only_known_ids ? drop_unknown_ids(known_ids_, detections) : 0;
  // One report per physical marker; a decoding the marker map knows wins (docs/detectors.md).
  drop_duplicate_detections(detections, [&](const Detection& d) {
    return options_.map && options_.map->find(d.family, d.id) != nullptr;
  });
  // One order whatever the detectors' threads did: families as listed, then id, then position.
  const auto rank = [&](const Detection& d) {
    return std::find(options_.families.begin(), options_.families.end(), d.family) -
           options_.families.begin();
  };
  std::stable_sort(detections.begin(), detections.end(),
                   [&](const Detection& a, const Detection& b) {
                     if (rank(a) != rank(b)) return rank(a) < rank(b);
                     if (a.id != b.id) return a.id < b.id;
                     if (a.corners_px.empty() || b.corners_px.empty()) return false;
                     return std::make_pair(a.corners_px[0].y(), a.corners_px[0].x()) <
                            std::make_pair(b.corners_px[0].y(), b.corners_px[0].x());
                   });
  return detections;
}

const FrameResult& Pipeline::process_projected(const PointView& cloud, double project_ms) {
  FrameResult& r = result_;
  r.markers.clear();
  r.pose.reset();
  r.pose_missing_reason.clear();
  r.pose_rejected = false;
  r.times_ms.project = project_ms;
  Stopwatch watch;

  preprocess(r.image, options_.preprocess, r.preprocessed);
  r.times_ms.preprocess = watch.lap_ms();

  std::vector<Detection> detections =
      detect_markers(detector_images(r.preprocessed, options_.preprocess), r);
  r.times_ms.detect = watch.lap_ms();
  lift_markers(detections, cloud, r);
  r.times_ms.lift = watch.lap_ms();

  r.threshold_retry.reset();
  // Nothing but chance matches the square check dropped, and no markers of ids not asked for
  // (--ids): the threshold shows no marker.
  const bool found_nothing = r.markers.empty() && r.unknown_ids_dropped == 0;
  const std::optional<double> otsu =
      found_nothing ? otsu_retry_threshold(r.preprocessed) : std::nullopt;
  r.times_ms.preprocess += watch.lap_ms();  // Otsu's histogram, else counted as the pose's
  const bool local = found_nothing && !otsu && options_.retry_with_local_threshold &&
                     fixed_threshold_may_be_retried(r.preprocessed);
  if (otsu || local) {
    if (otsu)
      binarize_at(r.preprocessed, *otsu, options_.preprocess, retry_detect_);
    else
      binarize_locally(r.preprocessed, options_.preprocess, retry_detect_);
    r.times_ms.preprocess += watch.lap_ms();
    DetectorImages images = detector_images(r.preprocessed, options_.preprocess);
    images.image = retry_detect_;
    detections = detect_markers(images, r);
    r.times_ms.detect += watch.lap_ms();
    lift_markers(detections, cloud, r);
    r.times_ms.lift += watch.lap_ms();
    r.threshold_retry = FrameResult::ThresholdRetry{r.preprocessed.threshold, otsu.value_or(0),
                                                    r.markers.size(), local};
    if (!r.markers.empty()) {
      std::swap(r.preprocessed.detect, retry_detect_);
      if (otsu) r.preprocessed.threshold = *otsu;
    }
  }

  if (!options_.map) {
    r.pose_missing_reason = "no marker map given";
  } else {
    std::vector<MarkerCorrespondence> correspondences;
    for (const MarkerResult& marker : r.markers) {
      if (!marker.in_map) continue;
      const MapMarker* mapped = options_.map->find(marker.detection.family, marker.detection.id);
      MarkerCorrespondence c{mapped->key(), {}, {}, {}, {}, marker.marker_fit_rms};
      const std::vector<Vec3> world = world_keypoints(marker.detection, *mapped);
      for (std::size_t k = 0; k < marker.corners.size() && k < world.size(); ++k) {
        if (!marker.corners[k].valid()) continue;
        c.world.push_back(world[k]);
        c.lidar.push_back(marker.lifted_points.empty() ? marker.corners[k].point
                                                       : marker.lifted_points[k]);
      }
      c.lidar_covariance = marker.corner_covariance;
      c.plane = marker.plane;
      if (!c.world.empty()) correspondences.push_back(std::move(c));
    }
    LidarPoseResult estimate = estimate_lidar_pose(correspondences, options_.pose);
    if (estimate.ok) {
      r.pose = std::move(estimate.pose);
    } else {
      r.pose_missing_reason = std::move(estimate.failure);
      r.pose_rejected = estimate.rejected;
    }
  }
  r.times_ms.pose = watch.lap_ms();
  return r;
}

}  // namespace iilfm
