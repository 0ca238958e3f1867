// `iilfm detect`: one cloud (or the first N clouds of a folder, integrated) through the pipeline.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "detect_image.hpp"
#include "detect_sequence.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/io/frame_source.hpp"
#include "iilfm/option_names.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/pose.hpp"
#include "iilfm/pose_covariance.hpp"
#include "iilfm/report.hpp"
#include "iilfm/report_html.hpp"
#include "iilfm/resolution.hpp"
#include "iilfm/sensor.hpp"
#include "opencv_threads.hpp"
#include "text_output.hpp"

namespace iilfm::cli {

namespace {

struct DetectArgs {
  std::string input;
  std::string sensor;
  double res_h = 0, res_v = 0;
  std::size_t max_image_pixels = ProjectionOptions{}.max_pixels;
  std::vector<std::string> markers;
  std::string ids;  // --ids: "0,3,10-19"
  std::string map_path;
  double marker_size = 0;
  int min_pose_corners = static_cast<int>(LidarPoseOptions{}.min_corners);
  double max_pose_rms = LidarPoseOptions{}.max_rms_m;
  std::string pose_refine = to_string(LidarPoseOptions{}.refine);
  int frames = 1;
  double window_seconds = 0;
  std::string threshold;
  std::string normalise_intensity;  // empty: the preset's
  std::string lift = "plane";
  std::string collision = "mean";
  std::string rows;
  bool no_square_pixels = false;
  bool no_edge_refine = false;
  bool no_search_regions = false;
  bool no_gray_decode = false;
  bool full_resolution_quads = false;
  bool no_ring_decode = false;
  bool no_square_check = false;
  bool ring_candidates = PipelineOptions{}.ring_candidates;
  double blur = 0;
  bool gray_input = false;
  float decimate = 1;
  float quad_sigma = 0;
  bool no_refine_edges = false;
  int threads = 1;
  int max_hamming = -1;
  std::string aruco_refine = "contour";
  int aruco_window_min = ArucoOptions{}.window_min;
  int aruco_window_max = ArucoOptions{}.window_max;
  int aruco_window_step = ArucoOptions{}.window_step;
  std::string json_path, image_path, html_path;
  std::string topic, jsonl_path, tum_path;  // sequences (detect_sequence.cpp)
  long html_frame = -1;
  bool quiet = false;
};

void append(PointCloud& into, const PointCloud& from) {
  into.x.insert(into.x.end(), from.x.begin(), from.x.end());
  into.y.insert(into.y.end(), from.y.begin(), from.y.end());
  into.z.insert(into.z.end(), from.z.begin(), from.z.end());
  into.intensity.insert(into.intensity.end(), from.intensity.begin(), from.intensity.end());
}

io::LoadedCloud load_input(const DetectArgs& args) {
  if (!std::filesystem::exists(args.input)) throw file_error(args.input, "no such file or folder");
  if (!std::filesystem::is_directory(args.input)) {
    if (args.frames != 1)
      throw file_error(args.input, "--frames needs a folder of cloud files to integrate");
    return io::read_cloud(args.input);
  }
  const std::vector<std::string> files = io::cloud_files_in(args.input);
  if (files.empty())
    throw file_error(args.input,
                     "folder holds no cloud files (.pcd, .bin, .ply, .txt, .xyz, .xyzi)");
  if (static_cast<std::size_t>(args.frames) > files.size())
    throw file_error(args.input, "--frames " + std::to_string(args.frames) +
                                     " but the folder holds " + std::to_string(files.size()) +
                                     " cloud files");
  io::LoadedCloud total;
  for (int i = 0; i < args.frames; ++i) {
    io::LoadedCloud frame = io::read_cloud(files[i]);
    append(total.cloud, frame.cloud);
    total.stats.points_in_file += frame.stats.points_in_file;
    total.stats.valid_points += frame.stats.valid_points;
    total.stats.non_finite += frame.stats.non_finite;
    total.stats.zero += frame.stats.zero;
  }
  return total;
}

// Where the image resolution came from, for the report and the JSON's image.resolution.
struct ResolutionOrigin {
  std::optional<ResolutionEstimate> estimated;  // no preset: all of it from the cloud
  std::optional<double> mode_step_deg;  // a spinning preset's columns, from the cloud's mode
};

// Without a preset or both resolutions, they come from the cloud; a spinning preset's column step
// comes from a single sweep when it runs in another mode (`origin` says which).
PipelineOptions pipeline_options(const DetectArgs& args, const PointCloud& cloud,
                                 ResolutionOrigin& origin) {
  PipelineOptions options;
  std::optional<ResolutionEstimate>& estimated = origin.estimated;
  if (!args.sensor.empty()) {
    const SensorPreset& preset = find_sensor_preset(args.sensor);
    apply_sensor_preset(preset, options);
    // Measured on single sweeps only: sweeps integrated at other azimuth phases (--frames,
    // --window-seconds) have finer gaps along a ring than the sensor's columns.
    if (args.res_h <= 0 && args.frames == 1 && args.window_seconds <= 0) {
      origin.mode_step_deg = mode_column_step(preset, cloud);
      if (origin.mode_step_deg) options.projection.res_h_deg = *origin.mode_step_deg;
    }
  } else if (args.res_h <= 0 || args.res_v <= 0) {
    try {
      estimated = estimate_resolution(cloud);
    } catch (const InputError& e) {
      throw file_error(args.input, e.what());
    }
    options.projection.res_h_deg = estimated->res_h_deg;
    options.projection.res_v_deg = estimated->res_v_deg;
    options.projection.rows = estimated->rows;
  }
  if (args.res_h > 0) options.projection.res_h_deg = args.res_h;
  if (args.res_v > 0) options.projection.res_v_deg = args.res_v;
  options.projection.max_pixels = args.max_image_pixels;

  set_intensity_normalisation(args.normalise_intensity, options);  // before --threshold
  set_threshold(args.threshold, options);
  options.preprocess.binarize = !args.gray_input;
  options.preprocess.blur_sigma = args.blur;

  set_rows(args.rows, options);
  options.preprocess.square_pixels = !args.no_square_pixels;
  options.edge_refine = !args.no_edge_refine;
  options.ring_decode = !args.no_ring_decode;
  if (args.no_square_check) options.max_square_error = 0;
  options.ring_candidates = args.ring_candidates;
  set_collision(args.collision, options);
  set_lift(args.lift, options);

  if (!args.markers.empty()) options.families = args.markers;
  if (!args.ids.empty()) set_known_ids(parse_id_list(args.ids), options);
  options.detector.apriltag.decimate = args.decimate;
  options.detector.apriltag.sigma = args.quad_sigma;
  options.detector.apriltag.refine_edges = !args.no_refine_edges;
  options.detector.apriltag.search_regions = !args.no_search_regions;
  options.detector.aruco.search_regions = !args.no_search_regions;
  options.detector.apriltag.decode_gray = !args.no_gray_decode;
  if (args.full_resolution_quads) options.detector.apriltag.half_resolution_px_per_cell = 0;
  set_threads(options, args.threads);
  options.detector.apriltag.max_hamming = args.max_hamming;
  options.detector.aruco.refine = aruco_refine_named(args.aruco_refine);
  options.detector.aruco.window_min = args.aruco_window_min;
  options.detector.aruco.window_max = args.aruco_window_max;
  options.detector.aruco.window_step = args.aruco_window_step;
  if (args.marker_size > 0) options.marker_size = args.marker_size;
  if (!args.map_path.empty()) options.map = MarkerMap::load(args.map_path);
  options.pose.min_corners = static_cast<std::size_t>(args.min_pose_corners);
  options.pose.refine = pose_refine_named(args.pose_refine);
  options.pose.max_rms_m = args.max_pose_rms;
  return options;
}

void print_summary(const FrameResult& r, const PipelineOptions& options,
                   const io::LoadedCloud& loaded, std::ostream& out) {
  const ImageGeometry& g = r.image.geometry;
  out << "cloud: " << loaded.stats.valid_points << " valid of " << loaded.stats.points_in_file
      << " points; image " << g.width << "x" << g.height << ", threshold "
      << r.preprocessed.threshold << "\n";
  if (r.preprocessed.no_intensity) {
    out << "warning: every point's intensity is 0: the cloud carries none (no intensity, "
           "reflectivity or i field?), and markers are seen in the intensity\n";
  } else if (r.preprocessed.replaced_threshold) {
    out << "note: the threshold " << *r.preprocessed.replaced_threshold
        << " lies above every intensity in the image (largest " << r.preprocessed.max_intensity
        << "): the cloud's intensity is not on the sensor preset's scale, so Otsu's threshold "
        << r.preprocessed.threshold << " was used (give --threshold to choose one)\n";
  } else if (r.preprocessed.threshold_above_all) {
    out << "warning: the threshold " << r.preprocessed.threshold
        << " lies above every intensity in the image (largest " << r.preprocessed.max_intensity
        << "), so no pixel is white; try --threshold otsu\n";
  }
  if (r.threshold_retry && r.threshold_retry->found > 0) {
    const FrameResult::ThresholdRetry& retry = *r.threshold_retry;
    out << "note: the sensor preset's threshold " << retry.fixed << " found no marker; ";
    if (retry.local)
      out << "the local threshold found " << retry.found
          << " (a far marker's cells averaged by the beam)\n";
    else
      out << "Otsu's threshold " << retry.otsu << " found " << retry.found
          << ": the print's intensity is not where the preset expects it (give --threshold to "
             "choose one)\n";
  }
  out << markers_found(r) << "\n";
  out << std::fixed << std::setprecision(3);
  for (const MarkerResult& m : r.markers) {
    out << "  " << m.detection.family << " id " << m.detection.id << ":";
    for (const LiftedCorner& c : m.corners) {
      if (c.valid())
        out << " (" << c.point.x() << ", " << c.point.y() << ", " << c.point.z() << ")";
      else
        out << " (unrecoverable)";
    }
    out << "\n";
    if (m.size_disagrees)
      out << "  note: it measures " << m.lifted_square->side_m << " m across its corners, not the "
          << given_size(options, m.detection).value_or(0)
          << " m given: the size is the black square's edge, without the white margin\n";
  }
  if (r.pose) {
    const Vec3 t = r.pose->T_world_lidar.translation();
    const Vec3 rpy = rpy_deg(r.pose->T_world_lidar.linear());
    out << "LiDAR pose in world: xyz (" << t.x() << ", " << t.y() << ", " << t.z() << ") m, rpy ("
        << rpy.x() << ", " << rpy.y() << ", " << rpy.z() << ") deg, rms " << r.pose->rms * 1000
        << " mm from " << r.pose->markers_used.size() << " marker(s)\n";
    const Vec3 sd_t = translation_std(r.pose->covariance) * 1000;
    const Vec3 sd_r = rpy_std_deg(r.pose->T_world_lidar, r.pose->covariance);
    out << "  1 sigma: xyz (" << sd_t.x() << ", " << sd_t.y() << ", " << sd_t.z() << ") mm, rpy ("
        << sd_r.x() << ", " << sd_r.y() << ", " << sd_r.z() << ") deg\n";
    for (const RejectedMarker& m : r.pose->markers_rejected)
      out << "  rejected " << m.key << ": " << m.residual_m * 1000
          << " mm from where the other markers put it (wrong id, moved, or map error?)\n";
  } else {
    out << "LiDAR pose: " << (r.pose_rejected ? "refused" : "none") << " (" << r.pose_missing_reason
        << ")\n";
  }
  out << "time: " << r.times_ms.total() << " ms (without reading)\n";
  out.unsetf(std::ios::fixed);
}

// Where the resolution came from, as the JSON's image.resolution says.
std::string resolution_source(const DetectArgs& args, const ResolutionOrigin& origin) {
  if (origin.estimated) return "estimated (" + origin.estimated->method + ")";
  return !args.sensor.empty() ? preset_resolution_source(args.sensor, origin.mode_step_deg)
                              : "given";
}

void report_resolution(const DetectArgs& args, const ResolutionOrigin& origin, std::ostream& out) {
  if (args.quiet) return;
  if (const std::optional<ResolutionEstimate>& estimated = origin.estimated) {
    out << "resolution estimated from the cloud (" << estimated->method
        << "): " << estimated->res_h_deg << " x " << estimated->res_v_deg << " deg";
    if (estimated->rings > 0) out << ", " << estimated->rings << " rings";
    out << " (give --sensor or --res-h/--res-v to set it)\n";
  } else if (origin.mode_step_deg) {
    const SensorPreset& preset = find_sensor_preset(args.sensor);
    out << "columns from the cloud: " << std::lround(360.0 / *origin.mode_step_deg) << " ("
        << *origin.mode_step_deg << " deg; preset " << preset.name << " assumes "
        << std::lround(360.0 / preset.res_h_deg) << "; --res-h sets it)\n";
  }
}

// The pipeline's own refusals (an image over --max-image-pixels) name the input file.
const FrameResult& process_or_explain(Pipeline& pipeline, const PointCloud& cloud,
                                      const std::string& input) {
  try {
    return pipeline.process(cloud);
  } catch (const InputError& e) {
    throw file_error(input, std::string(e.what()) + " (--max-image-pixels raises the limit)");
  }
}

int run_detect(const DetectArgs& args) {
  use_opencv_threads(args.threads);  // process-wide: once here, not with each pipeline's options
  const bool result_on_stdout = stdout_claimed(
      {{"--json", args.json_path}, {"--jsonl", args.jsonl_path}, {"--tum", args.tum_path}},
      {{"--image", args.image_path}, {"--html", args.html_path}});
  std::ostream& report = report_stream(result_on_stdout);
  if (!args.image_path.empty()) check_overlay_path(args.image_path);         // before any output
  if (!args.html_path.empty() && !html_report_available()) html_report({});  // throws why
  if (args.html_frame >= 0 && args.html_path.empty())
    throw InputError("--html-frame selects the frame the --html report of a sequence shows");
  if (is_image_input(args.input) && std::filesystem::is_regular_file(args.input)) {
    if (!args.html_path.empty())
      throw file_error(args.input, "--html needs a point cloud; an image gives --json and --image");
    if (!args.jsonl_path.empty() || !args.tum_path.empty() || !args.topic.empty())
      throw file_error(args.input,
                       "--jsonl, --tum and --topic take a recording; an image gives --json and "
                       "--image");
    if (!args.normalise_intensity.empty() && args.normalise_intensity != "none")
      throw file_error(args.input,
                       "--normalise-intensity needs a point cloud (an image has no range)");
    PipelineOptions options;
    ResolutionOrigin none;
    if (!args.sensor.empty() || (args.res_h > 0 && args.res_v > 0)) {
      options = pipeline_options(args, PointCloud{}, none);
    } else {
      // No geometry known: square pixels.
      DetectArgs square = args;
      square.res_h = square.res_v = 1;
      options = pipeline_options(square, PointCloud{}, none);
    }
    // An image has no range: a preset's normalisation does not apply.
    options.preprocess.normalise.mode = IntensityNormalisation::kNone;
    // A driver's 8-bit image is scaled for viewing, not in the cloud's intensity units, and one
    // global threshold over a room loses markers lit or ranged differently (the real Ouster image:
    // Otsu's keeps id 0 of its ids 0, 1 and 3): the local threshold unless --threshold says.
    if (args.threshold.empty()) {
      options.preprocess.threshold.reset();  // flat regions: Otsu's, in the image's gray levels
      options.preprocess.local_threshold = true;
    }
    return run_detect_image({args.input, args.json_path, args.image_path, args.quiet}, options);
  }
  SequenceArgs sequence;
  sequence.input = args.input;
  sequence.topic = args.topic;
  sequence.frames = args.frames;
  sequence.window_seconds = args.window_seconds;
  if (args.window_seconds > 0 && args.frames != 1)
    throw InputError("--frames and --window-seconds are alternatives: give one");
  sequence.jsonl_path = args.jsonl_path;
  sequence.tum_path = args.tum_path;
  sequence.html_path = args.html_path;
  sequence.html_frame = args.html_frame;
  sequence.quiet = args.quiet;
  if (is_sequence_run(sequence)) {
    if (!args.json_path.empty() || !args.image_path.empty())
      throw InputError(
          "--json and --image take one cloud; a sequence writes --jsonl, --tum and --html");
    return run_detect_sequence(sequence, [&](const PointCloud& first, std::string& source) {
      ResolutionOrigin origin;
      PipelineOptions options = pipeline_options(args, first, origin);
      report_resolution(args, origin, report);
      source = resolution_source(args, origin);
      return options;
    });
  }
  if (args.html_frame >= 0)
    throw InputError("--html-frame is for sequences (a bag, or a folder with --jsonl or --tum)");
  if (args.window_seconds > 0)
    throw InputError(
        "--window-seconds is for sequences (a bag, or a folder with --jsonl or --tum)");

  const auto start = std::chrono::steady_clock::now();
  io::LoadedCloud loaded = load_input(args);
  InputInfo info{
      args.input, loaded.stats,
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(),
      ""};
  if (loaded.cloud.empty()) {
    throw file_error(args.input, "no valid points (" + std::to_string(loaded.stats.non_finite) +
                                     " non-finite, " + std::to_string(loaded.stats.zero) +
                                     " zero, of " + std::to_string(loaded.stats.points_in_file) +
                                     ")");
  }

  ResolutionOrigin origin;
  Pipeline pipeline(pipeline_options(args, loaded.cloud, origin));
  info.resolution_source = resolution_source(args, origin);
  const FrameResult& result = process_or_explain(pipeline, loaded.cloud, args.input);
  // Printed only now, so a refused cloud leaves nothing on stdout.
  report_resolution(args, origin, report);
  if (!args.json_path.empty())
    write_text(args.json_path, result_to_json(result, info).dump(2) + "\n", "JSON");
  if (!args.image_path.empty()) write_overlay(args.image_path, result);
  if (!args.html_path.empty())
    write_html_report(args.html_path, {HtmlFrame{&result, info, PointView(loaded.cloud)}});
  if (!args.quiet) print_summary(result, pipeline.options(), loaded, report);
  return 0;
}

}  // namespace

Runner register_detect_command(CLI::App& app) {
  auto args = std::make_shared<DetectArgs>();
  CLI::App* cmd = app.add_subcommand("detect",
                                     "Detect markers in a point cloud and estimate the "
                                     "LiDAR pose");
  cmd->add_option("input", args->input,
                  "Cloud file (.pcd, .bin, .ply, .txt), folder of them, bag (.bag, ROS 2 "
                  "folder, .db3, .mcap), or an intensity image (.png: 2-D stages only)")
      ->required();
  cmd->add_option("--sensor", args->sensor, "Sensor preset (see `iilfm sensors`)");
  cmd->add_option("--res-h", args->res_h, "Horizontal angular resolution, degrees");
  cmd->add_option("--res-v", args->res_v, "Vertical angular resolution, degrees");
  cmd->add_option("--max-image-pixels", args->max_image_pixels,
                  "Refuse clouds whose intensity image would have more pixels than this")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--marker", args->markers,
                  "Marker family, repeatable (default apriltag:tag36h11)");
  cmd->add_option("--ids", args->ids,
                  "Ids of the markers in the scene, e.g. 0,3,10-19 (every --marker family): only "
                  "they are reported, and sparse rings read them farther (the map's ids are "
                  "always read so)");
  cmd->add_option("--map", args->map_path, "Marker map YAML: enables the LiDAR pose");
  cmd->add_option("--marker-size", args->marker_size,
                  "Edge of the black square (m) of markers not in the map: enables T_lidar_marker");
  cmd->add_option("--min-pose-corners", args->min_pose_corners,
                  "Fewest mapped corners a LiDAR pose needs (default 4; at least 3 are used)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--max-pose-rms", args->max_pose_rms,
                  "Largest corner RMS residual (m) of a reported LiDAR pose (default 0.05)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--pose-refine", args->pose_refine,
                  "LiDAR pose after Kabsch on the corners: none, or points (refined with each "
                  "marker's plane points)")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames,
                  "Integrate N frames: a folder alone gives one result for its first N files; "
                  "sequences slide an N-frame window")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--window-seconds", args->window_seconds,
                  "Sequences: integrate the frames taken less than S seconds before each frame "
                  "(frame stamps: bag headers, or numeric file names), instead of --frames")
      ->check(CLI::PositiveNumber);
  cmd->add_option(
      "--threshold", args->threshold,
      "Naive threshold in intensity units, 'otsu', or 'local' (local mean where the image "
      "has contrast; default: the preset's, retried at Otsu's when it finds no marker (a Livox "
      "preset's locally, where Otsu's is no other choice), or Otsu without a preset; 'local' for "
      "an image input)");
  cmd->add_option("--normalise-intensity", args->normalise_intensity,
                  "Intensity for range (x (r / 10 m)^2) and angle of incidence before "
                  "thresholding: none|range|range-incidence (default: the preset's, else none; "
                  "on, the threshold is Otsu's unless --threshold gives one in normalised units)");
  cmd->add_option("--lift", args->lift, "3-D corners: plane (marker-plane fit, default) or paper");
  cmd->add_option("--collision", args->collision, "Pixel value when points collide: mean|nearest");
  cmd->add_option("--rows", args->rows,
                  "Image rows: rings (one per laser; spinning presets) or uniform (res-v apart)");
  cmd->add_flag("--no-edge-refine", args->no_edge_refine,
                "Lift the detector's corners as found, without moving the sides to halfway "
                "between the marker's black and white levels");
  cmd->add_flag("--no-ring-decode", args->no_ring_decode,
                "On ring rows, do not check detections against the cells read from the rings "
                "that crossed them (nor keep the ones they confirm below one ring per cell)");
  cmd->add_flag("--no-square-check", args->no_square_check,
                "Keep detections whose lifted corners lie far from any square (chance matches on "
                "speckle are dropped by default)");
  cmd->add_flag("--ring-candidates,!--no-ring-candidates", args->ring_candidates,
                "On ring rows, also decode dark squares that no detector decoded from the rings "
                "that crossed them (default: range beyond one ring per cell row; a few ms a "
                "frame when such a square is in view)");
  cmd->add_flag("--no-square-pixels", args->no_square_pixels,
                "Give detectors the projected rows as they are (the paper's image)");
  cmd->add_option("--blur", args->blur, "Gaussian blur sigma (pixels) after thresholding");
  cmd->add_flag("--gray", args->gray_input, "Give detectors the gray image, not the binary one");
  cmd->add_option("--decimate", args->decimate, "AprilTag quad decimation (default 1)")
      ->check(CLI::Range(1.0, 8.0));
  cmd->add_option("--quad-sigma", args->quad_sigma, "AprilTag segmentation blur sigma (pixels)")
      ->check(CLI::Range(0.0, 10.0));
  cmd->add_flag("--no-refine-edges", args->no_refine_edges, "AprilTag: do not refine quad edges");
  cmd->add_flag("--no-search-regions", args->no_search_regions,
                "AprilTag and ArUco: search every pixel, not only the boxes around quad-shaped "
                "black-white boundaries of the binary image (same markers, slower)");
  cmd->add_flag("--no-gray-decode", args->no_gray_decode,
                "AprilTag: segment and decode the binary image itself, not the gray pixels inside "
                "its search regions");
  cmd->add_flag("--full-resolution-quads", args->full_resolution_quads,
                "AprilTag: find quads at full resolution in every search region, also where its "
                "outlines are large enough to find at half resolution (slower)");
  cmd->add_option(
         "--threads", args->threads,
         "threads for projecting and preprocessing large clouds, for running several families' "
         "detectors at once, for lifting markers and for OpenCV's own parallel loops (default 1)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--max-hamming", args->max_hamming, "Bits AprilTag may correct (-1: per family)");
  cmd->add_option("--aruco-refine", args->aruco_refine,
                  "ArUco corner refinement: none|subpixel|contour (default)|apriltag");
  cmd->add_option("--aruco-window-min", args->aruco_window_min,
                  "ArUco adaptive threshold: smallest window (pixels, default 3)")
      ->check(CLI::Range(3, 255));
  cmd->add_option("--aruco-window-max", args->aruco_window_max,
                  "ArUco adaptive threshold: largest window (pixels, default 23)")
      ->check(CLI::Range(3, 255));
  cmd->add_option("--aruco-window-step", args->aruco_window_step,
                  "ArUco adaptive threshold: window step (pixels, default 10)")
      ->check(CLI::Range(1, 255));
  cmd->add_option("--json", args->json_path, "Write the result as JSON (- for stdout)");
  cmd->add_option("--image", args->image_path,
                  "Write the intensity image with detections (.png, or .jpg for JPEG)");
  cmd->add_option("--html", args->html_path,
                  "Write a self-contained HTML report (3-D view, image, tables; sequences: the "
                  "trajectory and every frame's detections)");
  cmd->add_option("--html-frame", args->html_frame,
                  "Sequence --html: the frame shown in full (default: the last with markers)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--topic", args->topic, "Bag topic with the point clouds (bag input)");
  cmd->add_option("--jsonl", args->jsonl_path,
                  "Sequence: one JSON result per frame (JSON Lines; - for stdout)");
  cmd->add_option("--tum", args->tum_path,
                  "Sequence: LiDAR trajectory in TUM format (- for stdout)");
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success (and no progress bar)");
  return [args] { return run_detect(*args); };
}

}  // namespace iilfm::cli
