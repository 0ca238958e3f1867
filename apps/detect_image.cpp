#include "detect_image.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "iilfm/duplicates.hpp"
#include "iilfm/error.hpp"
#include "iilfm/image_files.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/report.hpp"
#include "iilfm/square_pixels.hpp"
#include "text_output.hpp"

namespace iilfm::cli {

namespace {
constexpr double kDegToRad = M_PI / 180.0;
}

bool is_image_input(const std::string& path) {
  const std::string ext = io::lower_extension(path);
  return ext == ".png" || ext == ".pgm" || ext == ".tif" || ext == ".tiff";
}

int run_detect_image(const ImageRunArgs& args, const PipelineOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const cv::Mat raw = read_intensity_image(args.path);

  // The image stands in for the projected intensity; 0 is "no return", as drivers write it.
  FrameResult result;
  ProjectedImage& image = result.image;
  raw.convertTo(image.intensity, CV_32F);
  image.mask = raw > 0;
  image.range = cv::Mat::zeros(raw.size(), CV_32F);
  image.index = cv::Mat(raw.size(), CV_32S, cv::Scalar(-1));
  image.count = image.mask / 255;
  image.count.convertTo(image.count, CV_32S);
  image.geometry.width = raw.cols;
  image.geometry.height = raw.rows;
  image.geometry.res_h = options.projection.res_h_deg * kDegToRad;
  image.geometry.res_v = options.projection.res_v_deg * kDegToRad;
  image.geometry.u0 = (raw.cols - 1) / 2.0;
  image.geometry.v0 = (raw.rows - 1) / 2.0;
  const double read_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  const auto detect_start = std::chrono::steady_clock::now();
  // Value 0 is both "no return" and black print here (a printed marker's PNG is 0 where black), so
  // holes stay black rather than taking their surroundings' class (a wide black border would
  // turn white inside).
  PreprocessOptions preprocess_options = options.preprocess;
  preprocess_options.hole_class_block = 0;
  preprocess(image, preprocess_options, result.preprocessed);
  const auto detected = std::chrono::steady_clock::now();
  result.times_ms.preprocess =
      std::chrono::duration<double, std::milli>(detected - detect_start).count();
  std::vector<Detection> detections;
  const DetectorImages images = detector_images(result.preprocessed, preprocess_options);
  for (const std::string& family : options.families)
    make_detector(family, options.detector)->detect_images(images, detections);
  drop_duplicate_detections(detections);  // one report per physical marker
  if (options.only_known_ids)
    result.unknown_ids_dropped = drop_unknown_ids(known_ids_of(options), detections);
  for (Detection& d : detections) {
    for (Vec2& px : d.corners_px) px = map_pixel(px, result.preprocessed.geometry, image.geometry);
    for (Vec2& px : d.outline_px) px = map_pixel(px, result.preprocessed.geometry, image.geometry);
    MarkerResult marker;
    marker.detection = std::move(d);
    result.markers.push_back(std::move(marker));
  }
  result.times_ms.detect =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - detected)
          .count();
  result.pose_missing_reason = "2-D image input: no 3-D points";

  if (!args.json_path.empty()) {
    CloudStats stats;
    stats.points_in_file = raw.total();
    stats.valid_points = static_cast<std::size_t>(cv::countNonZero(image.mask));
    const InputInfo info{args.path, stats, read_ms, "image pixels"};
    nlohmann::json j = result_to_json(result, info);
    j["input"]["kind"] = "image";
    write_text(args.json_path, j.dump(2) + "\n", "JSON");
  }
  if (!args.image_path.empty()) write_overlay(args.image_path, result);
  if (!args.quiet) {
    std::ostream& out = report_stream(is_stdout(args.json_path));
    out << "image: " << raw.cols << "x" << raw.rows << " (2-D stages only), threshold "
        << (options.preprocess.local_threshold ? "local (" : "") << result.preprocessed.threshold
        << (options.preprocess.local_threshold ? " where flat)" : "") << "\n"
        << markers_found(result) << "\n"
        << std::fixed << std::setprecision(1);
    for (const MarkerResult& m : result.markers) {
      out << "  " << m.detection.family << " id " << m.detection.id << ":";
      for (const Vec2& px : m.detection.corners_px) out << " (" << px.x() << ", " << px.y() << ")";
      out << " px\n";
    }
  }
  return 0;
}

}  // namespace iilfm::cli
