// iilfm.Pipeline and its results. Options mirror `iilfm detect`'s and are checked with the same
// messages; results carry numpy arrays (corners, 4x4 poses, the images).
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "bindings.hpp"
#include "iilfm/error.hpp"
#include "iilfm/frame_window.hpp"
#include "iilfm/marker_coverage.hpp"
#include "iilfm/option_names.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/pose.hpp"
#include "iilfm/report.hpp"
#include "iilfm/report_html.hpp"
#include "iilfm/resolution.hpp"
#include "points_input.hpp"

namespace iilfm::python {

namespace {

struct Options {
  std::optional<std::string> sensor;
  std::vector<std::string> markers;
  std::optional<std::string> map;
  std::optional<double> res_h, res_v, marker_size;
  std::optional<std::vector<int>> ids;
  py::object threshold;
  std::string normalise_intensity;  // empty: the preset's
  std::string lift = "plane", collision = "mean", aruco_refine = "contour";
  std::string pose_refine = to_string(LidarPoseOptions{}.refine);
  double blur = 0;
  bool gray = false, refine_edges = true;
  bool ring_decode = PipelineOptions{}.ring_decode;
  bool ring_candidates = PipelineOptions{}.ring_candidates;
  bool square_check = true;
  bool search_regions = AprilTagOptions{}.search_regions;
  bool gray_decode = AprilTagOptions{}.decode_gray;
  bool half_resolution = true;
  float decimate = 1, quad_sigma = 0;
  int threads = 1, max_hamming = -1;
  int aruco_window_min = ArucoOptions{}.window_min, aruco_window_max = ArucoOptions{}.window_max,
      aruco_window_step = ArucoOptions{}.window_step;
};

void require_range(double value, double lo, double hi, const char* name) {
  if (!(value >= lo && value <= hi))
    throw InputError(std::string(name) + " must be in [" +
                     py::str(py::float_(lo)).cast<std::string>() + ", " +
                     py::str(py::float_(hi)).cast<std::string>() + "], got " +
                     py::str(py::float_(value)).cast<std::string>());
}

// The same mapping and messages as `iilfm detect`'s options (apps/cmd_detect.cpp).
// Without a preset or both resolutions, PyPipeline estimates them from the first cloud.
PipelineOptions pipeline_options(const Options& a) {
  PipelineOptions options;
  if (a.sensor) apply_sensor_preset(find_sensor_preset(*a.sensor), options);
  if (a.res_h && *a.res_h > 0) options.projection.res_h_deg = *a.res_h;
  if (a.res_v && *a.res_v > 0) options.projection.res_v_deg = *a.res_v;

  set_intensity_normalisation(a.normalise_intensity, options);  // before the threshold
  if (py::isinstance<py::str>(a.threshold)) {
    set_threshold(a.threshold.cast<std::string>(), options);
  } else if (!a.threshold.is_none()) {
    const double t = a.threshold.cast<double>();
    if (!std::isfinite(t))
      throw InputError("--threshold must be a number, 'otsu' or 'local', got '" +
                       py::str(a.threshold).cast<std::string>() + "'");
    set_given_threshold(t, options);
  }
  options.preprocess.binarize = !a.gray;
  options.preprocess.blur_sigma = a.blur;

  set_collision(a.collision, options);
  set_lift(a.lift, options);
  options.pose.refine = pose_refine_named(a.pose_refine);
  options.ring_decode = a.ring_decode;
  options.ring_candidates = a.ring_candidates;
  if (!a.square_check) options.max_square_error = 0;

  // The ranges `iilfm detect` enforces on these options.
  require_range(a.decimate, 1, 8, "--decimate");
  require_range(a.quad_sigma, 0, 10, "--quad-sigma");
  require_range(a.threads, 1, 64, "--threads");
  require_range(a.aruco_window_min, 3, 255, "--aruco-window-min");
  require_range(a.aruco_window_max, 3, 255, "--aruco-window-max");
  require_range(a.aruco_window_step, 1, 255, "--aruco-window-step");

  if (!a.markers.empty()) options.families = a.markers;
  if (a.ids) set_known_ids(*a.ids, options);
  options.detector.apriltag.decimate = a.decimate;
  options.detector.apriltag.sigma = a.quad_sigma;
  options.detector.apriltag.refine_edges = a.refine_edges;
  options.detector.apriltag.search_regions = a.search_regions;
  options.detector.aruco.search_regions = a.search_regions;
  options.detector.apriltag.decode_gray = a.gray_decode;
  if (!a.half_resolution) options.detector.apriltag.half_resolution_px_per_cell = 0;
  set_threads(options, a.threads);
  options.detector.apriltag.max_hamming = a.max_hamming;
  options.detector.aruco.refine = aruco_refine_named(a.aruco_refine);
  options.detector.aruco.window_min = a.aruco_window_min;
  options.detector.aruco.window_max = a.aruco_window_max;
  options.detector.aruco.window_step = a.aruco_window_step;
  if (a.marker_size) {
    if (!(*a.marker_size > 0)) throw InputError("--marker-size must be positive (metres)");
    options.marker_size = *a.marker_size;
  }
  if (a.map) options.map = MarkerMap::load(*a.map);
  return options;
}

// A frame result that outlives the pipeline's reused buffers: every image is cloned.
std::shared_ptr<FrameResult> detached(const FrameResult& r) {
  auto copy = std::make_shared<FrameResult>(r);
  for (cv::Mat* m :
       {&copy->image.intensity, &copy->image.range, &copy->image.mask, &copy->image.index,
        &copy->image.count, &copy->preprocessed.gray, &copy->preprocessed.detect,
        &copy->preprocessed.valid, &copy->image.column_offset})
    *m = m->clone();
  return copy;
}

struct Marker {
  std::string family;
  int id = 0;
  py::object corners_px, corners_lidar, observed, T_lidar_marker, plane;
  double marker_fit_rms = 0, decision_margin = 0, coverage = 0;
  double measured_size = std::nan(""), square_rms = std::nan("");
  int hamming = 0;
  bool in_map = false;
  bool turn_known = true;
  bool size_disagrees = false;
};

struct Pose {
  py::object T_world_lidar, xyz, quat_xyzw, rpy_deg;
  double rms = 0;
  std::vector<std::string> markers_used;
  std::vector<std::pair<std::string, double>> markers_rejected;
  std::size_t corners_used = 0;
};

struct Result {
  std::shared_ptr<FrameResult> frame;
  std::shared_ptr<PointsInput> points;  // the frame's points (kept alive for write_html)
  InputInfo input;
  bool copied = false;
  std::vector<std::int32_t> original_row;
  std::vector<Marker> markers;
  std::optional<Pose> pose;
};

Marker marker_of(const MarkerResult& m, const ProjectedImage& image) {
  Marker out;
  out.family = m.detection.family;
  out.id = m.detection.id;
  const auto k = static_cast<py::ssize_t>(m.detection.corners_px.size());
  py::array_t<double> px({k, py::ssize_t{2}}), lidar({k, py::ssize_t{3}});
  py::array_t<bool> observed(k);
  auto p = px.mutable_unchecked<2>();
  auto l = lidar.mutable_unchecked<2>();
  auto o = observed.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < k; ++i) {
    const LiftedCorner& c = m.corners[static_cast<std::size_t>(i)];
    p(i, 0) = m.detection.corners_px[static_cast<std::size_t>(i)].x();
    p(i, 1) = m.detection.corners_px[static_cast<std::size_t>(i)].y();
    // An unrecoverable corner is NaN: never a made-up point.
    for (int d = 0; d < 3; ++d) l(i, d) = c.valid() ? c.point[d] : std::nan("");
    o(i) = c.status == CornerStatus::kObserved;
  }
  out.corners_px = px;
  out.corners_lidar = lidar;
  out.observed = observed;
  out.T_lidar_marker =
      m.T_lidar_marker ? py::object(to_numpy(m.T_lidar_marker->matrix())) : py::object(py::none());
  out.marker_fit_rms = m.marker_fit_rms;
  if (m.lifted_square) {
    out.measured_size = m.lifted_square->side_m;
    out.square_rms = m.lifted_square->rms_m;
  }
  out.size_disagrees = m.size_disagrees;
  out.decision_margin = m.detection.decision_margin;
  out.hamming = m.detection.hamming;
  out.in_map = m.in_map;
  out.turn_known = m.turn_known;
  out.coverage = marker_coverage(m.detection, image);
  out.plane = py::none();
  if (m.plane && m.plane->ok) {
    py::dict plane;
    plane["normal"] = to_numpy(m.plane->normal.transpose()).attr("ravel")();
    plane["d"] = m.plane->d;
    plane["points"] = m.plane->inliers;
    plane["rms"] = m.plane->rms;
    plane["surround_scale"] = m.plane->surround_scale;
    out.plane = plane;
  }
  return out;
}

Pose pose_of(const LidarPose& p) {
  Pose out;
  out.T_world_lidar = to_numpy(p.T_world_lidar.matrix());
  out.xyz = to_numpy(Vec3(p.T_world_lidar.translation()).transpose()).attr("ravel")();
  const Eigen::Quaterniond q(p.T_world_lidar.linear());
  out.quat_xyzw = to_numpy(Eigen::RowVector4d(q.x(), q.y(), q.z(), q.w())).attr("ravel")();
  out.rpy_deg = to_numpy(rpy_deg(p.T_world_lidar.linear()).transpose()).attr("ravel")();
  out.rms = p.rms;
  out.markers_used = p.markers_used;
  for (const RejectedMarker& r : p.markers_rejected)
    out.markers_rejected.emplace_back(r.key, r.residual_m);
  out.corners_used = p.corners_used;
  return out;
}

// The result's JSON exactly as `iilfm detect --json` writes it, as Python objects.
py::object json_of(const Result& r) {
  return py::module_::import("json").attr("loads")(result_to_json(*r.frame, r.input).dump());
}

class PyPipeline {
 public:
  explicit PyPipeline(const Options& o) : options_(pipeline_options(o)) {
    const bool given = o.res_h && o.res_v && *o.res_h > 0 && *o.res_v > 0;
    const SensorPreset* preset = o.sensor ? &find_sensor_preset(*o.sensor) : nullptr;
    if (preset && preset->kind == ScanKind::kSpinning && !(o.res_h && *o.res_h > 0)) {
      // As `iilfm detect --sensor`: the columns of the first cloud's mode (mode_column_step).
      mode_preset_ = *preset;
      Pipeline check(options_);
      return;
    }
    if (o.sensor || given) {
      resolution_source_ = o.sensor ? preset_resolution_source(*o.sensor, std::nullopt) : "given";
      pipeline_.emplace(options_);
      return;
    }
    // As `iilfm detect` without --sensor: from the first cloud, a given res_h or res_v kept.
    if (o.res_h && *o.res_h > 0) given_res_h_ = *o.res_h;
    if (o.res_v && *o.res_v > 0) given_res_v_ = *o.res_v;
    Pipeline check(options_);  // bad families and sizes raise now, not at the first detect()
  }

  Result detect(const py::handle& points) { return run(points_from_python(points)); }

  // Every frame, or every window of `window` frames sliding by one (as `iilfm detect` on a
  // recording with --frames): a Result per full window.
  std::vector<Result> detect_frames(const py::iterable& frames, std::size_t window) {
    if (window < 1) throw InputError("window must be at least 1 (frames)");
    windows_ = window > 1;
    std::vector<Result> results;
    FrameWindow held(window);
    for (const py::handle& frame : frames) {
      std::unique_ptr<PointsInput> in = points_from_python(frame);
      if (window == 1) {
        results.push_back(run(std::move(in)));
        continue;
      }
      held.push(copy_of(in->view), in->stats);
      if (held.full()) results.push_back(run(points_owning(held.copy(), held.stats(), in->path)));
    }
    return results;
  }

  // The resolution used, and where it came from; None until an estimate was made.
  py::object resolution() const {
    if (!pipeline_) return py::none();
    const ProjectionOptions& p = pipeline_->options().projection;
    py::dict d;
    d["res_h_deg"] = p.res_h_deg;
    d["res_v_deg"] = p.res_v_deg;
    d["rows"] = p.rows == RowLayout::kRings ? "rings" : "uniform";
    d["source"] = resolution_source_;
    if (estimated_) d["rings"] = estimated_->rings;
    return d;
  }

  std::uintptr_t last_x_address() const { return last_x_address_; }

 private:
  // The pipeline, made now from the first cloud's resolution when it is to be estimated.
  Pipeline& pipeline_for(const PointsInput& in) {
    if (pipeline_) return *pipeline_;
    if (mode_preset_) {
      PipelineOptions options = options_;
      // Not on a window of integrated sweeps: their gaps along a ring are finer than the columns.
      const std::optional<double> step =
          windows_ ? std::nullopt : mode_column_step(*mode_preset_, copy_of(in.view));
      if (step) options.projection.res_h_deg = *step;
      resolution_source_ = preset_resolution_source(mode_preset_->name, step);
      return pipeline_.emplace(options);
    }
    try {
      estimated_ = estimate_resolution(copy_of(in.view));
    } catch (const InputError& e) {
      throw file_error(in.path.empty() ? "points" : in.path, e.what());
    }
    PipelineOptions options = options_;
    options.projection.res_h_deg = given_res_h_.value_or(estimated_->res_h_deg);
    options.projection.res_v_deg = given_res_v_.value_or(estimated_->res_v_deg);
    options.projection.rows = estimated_->rows;
    resolution_source_ = "estimated (" + estimated_->method + ")";
    return pipeline_.emplace(options);
  }

  Result run(std::unique_ptr<PointsInput> in) {
    Pipeline& pipeline = pipeline_for(*in);
    Result r;
    {
      py::gil_scoped_release release;
      r.frame = detached(pipeline.process(in->view));
    }
    last_x_address_ = reinterpret_cast<std::uintptr_t>(in->view.x.data);
    r.input = InputInfo{in->path.empty() ? "<array>" : in->path, in->stats, 0, resolution_source_};
    r.copied = in->copied;
    r.original_row = in->original_row;
    r.points = std::move(in);
    for (const MarkerResult& m : r.frame->markers)
      r.markers.push_back(marker_of(m, r.frame->image));
    if (r.frame->pose) r.pose = pose_of(*r.frame->pose);
    return r;
  }

  PipelineOptions options_;
  std::optional<Pipeline> pipeline_;
  std::optional<double> given_res_h_, given_res_v_;
  std::optional<ResolutionEstimate> estimated_;
  std::optional<SensorPreset> mode_preset_;  // a spinning preset whose columns the cloud sets
  bool windows_ = false;                     // detect_frames integrates windows of sweeps
  std::uintptr_t last_x_address_ = 0;
  std::string resolution_source_;  // as the CLI's JSON names it
};

py::array index_image(const py::object& self) {
  const Result& r = self.cast<const Result&>();
  if (r.original_row.empty()) return mat_view(r.frame->image.index, self);
  // Points were skipped into a copy: report rows of the caller's input.
  const cv::Mat& index = r.frame->image.index;
  py::array_t<std::int32_t> out({index.rows, index.cols});
  auto w = out.mutable_unchecked<2>();
  for (int row = 0; row < index.rows; ++row)
    for (int col = 0; col < index.cols; ++col) {
      const std::int32_t i = index.at<std::int32_t>(row, col);
      w(row, col) = i < 0 ? -1 : r.original_row[static_cast<std::size_t>(i)];
    }
  return out;
}

}  // namespace

void register_pipeline(py::module_& m) {
  py::class_<Marker>(m, "Marker", "One detected marker.")
      .def_readonly("family", &Marker::family, "e.g. 'apriltag:tag36h11'")
      .def_readonly("id", &Marker::id)
      .def_readonly("corners_px", &Marker::corners_px,
                    "(K, 2) float64 sub-pixel corners in the intensity image (pixel centres at "
                    "integers), top-left, top-right, bottom-right, bottom-left")
      .def_readonly("corners_lidar", &Marker::corners_lidar,
                    "(K, 3) float64 corners in the LiDAR frame, metres; NaN rows for corners that "
                    "could not be lifted")
      .def_readonly("observed", &Marker::observed,
                    "(K,) bool: the corner's pixel held points (not interpolated)")
      .def_readonly("T_lidar_marker", &Marker::T_lidar_marker,
                    "(4, 4) float64 marker pose in the LiDAR frame, or None when the size is "
                    "unknown (give map= or marker_size=)")
      .def_readonly("turn_known", &Marker::turn_known,
                    "False for ring markers: T_lidar_marker's turn about the face normal is a "
                    "convention (y as near the LiDAR's up as the face allows), not measured")
      .def_readonly("marker_fit_rms", &Marker::marker_fit_rms,
                    "metres: how far the lifted corners were from a square of the known size")
      .def_readonly("measured_size", &Marker::measured_size,
                    "metres: edge of the nearest square to the four lifted corners (NaN when a "
                    "corner did not lift, or for boards and ring markers)")
      .def_readonly("square_rms", &Marker::square_rms,
                    "metres: how far the lifted corners were from that square")
      .def_readonly("size_disagrees", &Marker::size_disagrees,
                    "the measured size differs from the known one (map or marker_size) by more "
                    "than a tenth plus two pixel footprints: the size given is likely not the "
                    "black square's edge")
      .def_readonly("hamming", &Marker::hamming, "bits corrected while decoding")
      .def_readonly("decision_margin", &Marker::decision_margin, "decoder's confidence")
      .def_readonly("in_map", &Marker::in_map, "the marker is in the marker map")
      .def_readonly("coverage", &Marker::coverage,
                    "share of the marker's image pixels holding a point (before hole filling)")
      .def_readonly("plane", &Marker::plane,
                    "the fitted marker plane (plane lifting), else None: a dict with normal "
                    "((3,) float64) and d (normal . x = d in the LiDAR frame, metres), points, "
                    "rms (metres) and surround_scale (> 1: the normal came from the wall around "
                    "the marker, that many times its size)")
      .def("__repr__", [](const Marker& mk) {
        return "<iilfm.Marker " + mk.family + " id " + std::to_string(mk.id) + ">";
      });

  py::class_<Pose>(m, "Pose", "The LiDAR's pose in the world, from the mapped markers.")
      .def_readonly("T_world_lidar", &Pose::T_world_lidar,
                    "(4, 4) float64: maps LiDAR points into the world")
      .def_readonly("xyz", &Pose::xyz, "(3,) LiDAR position in the world, metres")
      .def_readonly("quat_xyzw", &Pose::quat_xyzw, "(4,) orientation quaternion x, y, z, w")
      .def_readonly("rpy_deg", &Pose::rpy_deg, "(3,) roll, pitch, yaw in degrees (extrinsic xyz)")
      .def_readonly("rms", &Pose::rms, "corner residual after alignment, metres")
      .def_readonly("markers_used", &Pose::markers_used, "'family/id' of the markers used")
      .def_readonly("markers_rejected", &Pose::markers_rejected,
                    "('family/id', residual metres) of mapped markers left out as inconsistent")
      .def_readonly("corners_used", &Pose::corners_used);

  py::class_<Result>(m, "Result", "What Pipeline.detect found in one frame.")
      .def_readonly("markers", &Result::markers, "list of Marker")
      .def_property_readonly(
          "pose",
          [](const Result& r) -> py::object { return r.pose ? py::cast(*r.pose) : py::none(); },
          "Pose, or None (see pose_missing_reason)")
      .def_property_readonly(
          "pose_missing_reason", [](const Result& r) { return r.frame->pose_missing_reason; },
          "why pose is None ('' when there is a pose)")
      .def_property_readonly(
          "markers_not_reported", [](const Result& r) { return r.frame->unknown_ids_dropped; },
          "markers found whose ids were not among the ids= given, so left out of markers")
      .def_property_readonly(
          "detections_not_square", [](const Result& r) { return r.frame->not_square_dropped; },
          "detections dropped because their lifted corners are no square (chance matches)")
      .def_property_readonly(
          "intensity_image",
          [](py::object self) {
            return mat_view(self.cast<Result&>().frame->image.intensity, self);
          },
          "(H, W) float32 intensity image (0 where unobserved)")
      .def_property_readonly(
          "range_image",
          [](py::object self) { return mat_view(self.cast<Result&>().frame->image.range, self); },
          "(H, W) float32 range image in metres (0 where unobserved)")
      .def_property_readonly(
          "mask",
          [](py::object self) { return mat_view(self.cast<Result&>().frame->image.mask, self); },
          "(H, W) uint8, 255 where a point fell")
      .def_property_readonly(
          "column_offset_image",
          [](py::object self) -> py::object {
            const cv::Mat& offsets = self.cast<Result&>().frame->image.column_offset;
            if (offsets.empty()) return py::none();
            return mat_view(offsets, self);
          },
          "(H, W) float32: where each single-point pixel's sample lies, in columns right of "
          "its centre (a spinning LiDAR's rings fire off the column grid); 0 for other pixels. "
          "None when every ring lies on the grid, and for uniform rows")
      .def_property_readonly("index_image", &index_image,
                             "(H, W) int32 row of an input point in each pixel, -1 where none: "
                             "its only point; where several fell, the last of them (the nearest "
                             "with collision='nearest'; -1 in a sliding window)")
      .def_property_readonly(
          "gray_image",
          [](py::object self) {
            return mat_view(self.cast<Result&>().frame->preprocessed.gray, self);
          },
          "(H, W) uint8 preprocessed intensity image (display scale, holes filled)")
      .def_property_readonly(
          "detect_image",
          [](py::object self) {
            return mat_view(self.cast<Result&>().frame->preprocessed.detect, self);
          },
          "(H, W) uint8 image the detectors saw (binary unless gray=True)")
      .def_property_readonly(
          "threshold", [](const Result& r) { return r.frame->preprocessed.threshold; },
          "threshold applied, intensity units")
      .def_property_readonly(
          "image",
          [](const Result& r) {
            const ImageGeometry& g = r.frame->image.geometry;
            py::dict d;
            d["width"] = g.width;
            d["height"] = g.height;
            d["res_h_deg"] = g.res_h * 180 / M_PI;
            d["res_v_deg"] = g.res_v * 180 / M_PI;
            d["u0"] = g.u0;
            d["v0"] = g.v0;
            return d;
          },
          "image geometry: width, height, res_h_deg, res_v_deg, u0, v0 (column/row of azimuth "
          "and elevation 0)")
      .def_property_readonly(
          "timing_ms",
          [](const Result& r) {
            const StageTimes& t = r.frame->times_ms;
            py::dict d;
            d["project"] = t.project;
            d["preprocess"] = t.preprocess;
            d["detect"] = t.detect;
            d["lift"] = t.lift;
            d["pose"] = t.pose;
            d["total"] = t.total();
            return d;
          },
          "milliseconds per stage")
      .def_property_readonly(
          "input",
          [](const Result& r) {
            py::dict d;
            d["path"] = r.input.path;
            d["points"] = r.input.stats.points_in_file;
            d["valid_points"] = r.input.stats.valid_points;
            d["non_finite"] = r.input.stats.non_finite;
            d["zero"] = r.input.stats.zero;
            d["copied"] = r.copied;
            return d;
          },
          "points given, kept and skipped, and whether the points had to be copied")
      .def("to_json", &json_of,
           "The result as `iilfm detect --json` writes it (dict of plain Python values).")
      .def(
          "overlay",
          [](const Result& r) {
            const cv::Mat bgr = draw_overlay(*r.frame);
            py::array_t<std::uint8_t> rgb({bgr.rows, bgr.cols, 3});
            auto w = rgb.mutable_unchecked<3>();
            for (int y = 0; y < bgr.rows; ++y)
              for (int x = 0; x < bgr.cols; ++x) {
                const cv::Vec3b& p = bgr.at<cv::Vec3b>(y, x);
                w(y, x, 0) = p[2];
                w(y, x, 1) = p[1];
                w(y, x, 2) = p[0];
              }
            return rgb;
          },
          "The picture `iilfm detect --image` writes, as an (H, W, 3) uint8 RGB array.")
      .def(
          "write_html",
          [](const Result& r, const std::filesystem::path& path, const std::string& title,
             std::size_t max_points) {
            HtmlReportOptions options;
            options.title = title;
            options.max_points = max_points;
            write_html_report(path.string(), {HtmlFrame{r.frame.get(), r.input, r.points->view}},
                              options);
          },
          py::arg("path"), py::arg("title") = HtmlReportOptions{}.title,
          py::arg("max_points") = HtmlReportOptions{}.max_points,
          "Writes the self-contained HTML report of this frame, as `iilfm detect --html` does "
          "(3-D view of the points given to detect(), image, tables).")
      .def("__repr__", [](const Result& r) {
        return "<iilfm.Result " + std::to_string(r.markers.size()) + " marker(s), " +
               (r.pose ? "pose" : "no pose") + ">";
      });

  py::class_<PyPipeline>(m, "Pipeline",
                         "Detection pipeline: projection, preprocessing, detection, lifting, "
                         "pose. Options mirror `iilfm detect`'s; one Pipeline per thread.")
      .def(
          py::init([](std::optional<std::string> sensor, std::vector<std::string> markers,
                      std::optional<std::filesystem::path> map, std::optional<double> res_h,
                      std::optional<double> res_v, std::optional<double> marker_size,
                      std::optional<std::vector<int>> ids, py::object threshold, std::string lift,
                      std::string collision, double blur, bool gray, float decimate,
                      float quad_sigma, bool refine_edges, int threads, int max_hamming,
                      std::string aruco_refine, int aruco_window_min, int aruco_window_max,
                      int aruco_window_step, std::string pose_refine,
                      std::string normalise_intensity, bool ring_decode, bool ring_candidates,
                      bool search_regions, bool gray_decode, bool half_resolution,
                      bool square_check) {
            Options o;
            o.sensor = std::move(sensor);
            o.markers = std::move(markers);
            if (map) o.map = map->string();
            o.res_h = res_h;
            o.res_v = res_v;
            o.marker_size = marker_size;
            o.ids = std::move(ids);
            o.threshold = std::move(threshold);
            o.lift = std::move(lift);
            o.collision = std::move(collision);
            o.blur = blur;
            o.gray = gray;
            o.decimate = decimate;
            o.quad_sigma = quad_sigma;
            o.refine_edges = refine_edges;
            o.threads = threads;
            o.max_hamming = max_hamming;
            o.aruco_refine = std::move(aruco_refine);
            o.aruco_window_min = aruco_window_min;
            o.aruco_window_max = aruco_window_max;
            o.aruco_window_step = aruco_window_step;
            o.pose_refine = std::move(pose_refine);
            o.normalise_intensity = std::move(normalise_intensity);
            o.ring_decode = ring_decode;
            o.ring_candidates = ring_candidates;
            o.search_regions = search_regions;
            o.gray_decode = gray_decode;
            o.half_resolution = half_resolution;
            o.square_check = square_check;
            return std::make_unique<PyPipeline>(o);
          }),
          py::arg("sensor") = py::none(), py::arg("markers") = std::vector<std::string>{},
          py::arg("map") = py::none(), py::kw_only(), py::arg("res_h") = py::none(),
          py::arg("res_v") = py::none(), py::arg("marker_size") = py::none(),
          py::arg("ids") = py::none(), py::arg("threshold") = py::none(), py::arg("lift") = "plane",
          py::arg("collision") = "mean", py::arg("blur") = 0.0, py::arg("gray") = false,
          py::arg("decimate") = 1.0f, py::arg("quad_sigma") = 0.0f, py::arg("refine_edges") = true,
          py::arg("threads") = 1, py::arg("max_hamming") = -1, py::arg("aruco_refine") = "contour",
          py::arg("aruco_window_min") = ArucoOptions{}.window_min,
          py::arg("aruco_window_max") = ArucoOptions{}.window_max,
          py::arg("aruco_window_step") = ArucoOptions{}.window_step,
          py::arg("pose_refine") = to_string(LidarPoseOptions{}.refine),
          py::arg("normalise_intensity") = "",
          py::arg("ring_decode") = PipelineOptions{}.ring_decode,
          py::arg("ring_candidates") = PipelineOptions{}.ring_candidates,
          py::arg("search_regions") = AprilTagOptions{}.search_regions,
          py::arg("gray_decode") = AprilTagOptions{}.decode_gray, py::arg("half_resolution") = true,
          py::arg("square_check") = true,
          "sensor: preset name (`iilfm sensors`), or give res_h and res_v in degrees; with "
          "neither, the resolution is estimated from the first cloud detected (as `iilfm "
          "detect` does without --sensor) and kept for later frames (see resolution).\n"
          "markers: families, e.g. ['apriltag:tag36h11', 'aruco:DICT_4X4_50'] "
          "(default apriltag:tag36h11).\n"
          "map: marker map YAML path; enables the LiDAR pose.\n"
          "ids: the ids of the markers in the scene (every family), as --ids: only they are "
          "reported, and sparse rings read them farther (the map's ids are always read so).\n"
          "Other keywords are `iilfm detect`'s options with '-' as '_' (threshold: number or "
          "'otsu'; normalise_intensity: 'none', 'range' or 'range-incidence', '' = the preset's; "
          "refine_edges=False is --no-refine-edges; gray=True is --gray; ring_decode=False is "
          "--no-ring-decode; ring_candidates=False is --no-ring-candidates; search_regions=False "
          "is --no-search-regions; gray_decode=False is --no-gray-decode; half_resolution=False is "
          "--full-resolution-quads; square_check=False is --no-square-check).\n"
          "Raises InputError with the program's message for bad options, presets or maps.")
      .def("detect", &PyPipeline::detect, py::arg("points"),
           "Runs every stage on one frame. points: an (N, >=4) array of x, y, z, intensity[, ...] "
           "(float32 is read in place, any strides; other dtypes are converted once), a dict of "
           "1-D columns x, y, z, intensity[, ring], or an iilfm.Cloud. NaN/Inf and (0, 0, 0) "
           "points are skipped like the file readers skip them (that needs one copy). "
           "Result.input['copied'] tells whether a copy was made.")
      .def("detect_frames", &PyPipeline::detect_frames, py::arg("frames"), py::arg("window") = 1,
           "Runs a recording: frames is an iterable of what detect() takes. window=1 gives one "
           "Result per frame (read in place like detect()); window=N integrates the last N "
           "frames, sliding by one (as `iilfm detect` on a recording with --frames N), one "
           "Result per full window (len(frames) - N + 1), over a copy of their union.")
      .def_property_readonly(
          "resolution", &PyPipeline::resolution,
          "dict res_h_deg, res_v_deg, rows ('rings' or 'uniform'), source ('preset mid40', "
          "'given', 'estimated (ring field)', ...) and, when estimated, rings; None before the "
          "first detect() when the resolution is to be estimated.")
      .def("_last_x_address", &PyPipeline::last_x_address,
           "Debug: address of the x values the last detect() read (for no-copy tests).");
}

}  // namespace iilfm::python
