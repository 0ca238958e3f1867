// Several Pipeline objects, one per thread, on different scans at once give exactly what each gives
// alone: nothing in the pipeline, its detectors or its options is shared mutable state. The same
// for a pipeline's own threads (projection, preprocessing, lift). Built and run under
// ThreadSanitizer by scripts/tsan.sh (CI), which also reports any data race it sees.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "iilfm/pipeline.hpp"
#include "iilfm/preprocess.hpp"
#include "iilfm/projection.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/sim/scenes.hpp"
#include "iilfm/sim/simulate.hpp"

namespace iilfm {
namespace {

constexpr int kThreads = 4;

// The "around" room (five markers on four walls, an OS1-64 in the middle), one noise seed per
// scan, so every thread has its own cloud.
struct Scans {
  std::vector<sim::SimResult> scans;
  MarkerMap map;
};

const Scans& scans() {
  static const Scans all = [] {
    Scans s;
    const sim::SceneSetup setup = sim::named_scene("around");
    for (int k = 0; k < kThreads; ++k) {
      sim::SimOptions options;
      options.T_world_lidar = setup.T_world_lidar;
      options.seed = 11 + k;
      s.scans.push_back(sim::simulate(setup.scene, sim::sensor_model(setup.sensor), options));
    }
    for (const sim::MarkerTruth& m : s.scans[0].truth.markers) {
      MapMarker marker;
      marker.family = m.family;
      marker.id = m.id;
      marker.corners_world = m.corners_world;
      s.map.add(marker);
    }
    return s;
  }();
  return all;
}

PipelineOptions os1_options() {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("os1-64"), options);
  options.map = scans().map;
  return options;
}

// 20 Mid-40 frames of a named scene, and the Mid-40 preset's options.
sim::SimResult mid40_scan(const std::string& scene) {
  const sim::SceneSetup setup = sim::named_scene(scene);
  sim::SimOptions options;
  options.T_world_lidar = setup.T_world_lidar;
  options.frames = 20;
  return sim::simulate(setup.scene, sim::sensor_model(setup.sensor), options);
}

PipelineOptions mid40_options() {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid40"), options);
  return options;
}

// What a test compares: every detection's id, image corners and lifted corners, and the pose.
struct Outcome {
  std::vector<int> ids;
  std::vector<Vec2> corners_px;
  std::vector<Vec3> corners_3d;
  std::optional<Isometry3> pose;
};

Outcome outcome_of(const FrameResult& r) {
  Outcome o;
  for (const MarkerResult& m : r.markers) {
    o.ids.push_back(m.detection.id);
    for (const Vec2& c : m.detection.corners_px) o.corners_px.push_back(c);
    for (const LiftedCorner& c : m.corners) o.corners_3d.push_back(c.point);
  }
  if (r.pose) o.pose = r.pose->T_world_lidar;
  return o;
}

void expect_identical(const Outcome& a, const Outcome& b, int scan) {
  EXPECT_EQ(a.ids, b.ids) << "scan " << scan;
  ASSERT_EQ(a.corners_px.size(), b.corners_px.size()) << "scan " << scan;
  for (std::size_t i = 0; i < a.corners_px.size(); ++i)
    EXPECT_EQ(a.corners_px[i], b.corners_px[i]) << "scan " << scan << " corner " << i;
  ASSERT_EQ(a.corners_3d.size(), b.corners_3d.size()) << "scan " << scan;
  for (std::size_t i = 0; i < a.corners_3d.size(); ++i)
    EXPECT_EQ(a.corners_3d[i], b.corners_3d[i]) << "scan " << scan << " corner " << i;
  ASSERT_EQ(a.pose.has_value(), b.pose.has_value()) << "scan " << scan;
  if (a.pose) {
    EXPECT_EQ(a.pose->matrix(), b.pose->matrix()) << "scan " << scan;
  }
}

TEST(ParallelPipelines, OnePerThreadGiveTheSingleThreadedResults) {
  std::vector<Outcome> alone;
  for (int k = 0; k < kThreads; ++k) {
    Pipeline pipeline(os1_options());
    alone.push_back(outcome_of(pipeline.process(scans().scans[k].cloud)));
    // Three of the five markers are found in one OS1-64 sweep (the one behind sits on the image
    // seam); a test that found none would compare nothing.
    EXPECT_GE(alone.back().ids.size(), 3u) << "scan " << k;
    EXPECT_TRUE(alone.back().pose) << "scan " << k;
  }

  // Each thread builds its own pipeline and runs its scan twice (the second run reuses the
  // buffers of the first), all threads at the same time.
  std::vector<Outcome> first(kThreads), second(kThreads);
  std::vector<std::thread> threads;
  for (int k = 0; k < kThreads; ++k) {
    threads.emplace_back([k, &first, &second] {
      Pipeline pipeline(os1_options());
      first[k] = outcome_of(pipeline.process(scans().scans[k].cloud));
      second[k] = outcome_of(pipeline.process(scans().scans[k].cloud));
    });
  }
  for (std::thread& t : threads) t.join();
  for (int k = 0; k < kThreads; ++k) {
    expect_identical(alone[k], first[k], k);
    expect_identical(alone[k], second[k], k);
  }
}

TEST(ProjectionThreads, SplitPassesGiveTheOneThreadImages) {
  // The projector's own helper threads (ProjectionOptions::threads): points and pixels split
  // between them, under ThreadSanitizer here. Uniform 0.1 deg rows make a 1.6-million-pixel image
  // of the OS1-64 sweep, so the pixel passes split as well as the point passes.
  const PointCloud& cloud = scans().scans[0].cloud;
  ProjectionOptions options;
  options.res_h_deg = options.res_v_deg = 0.1;
  ProjectedImage one, three;
  SphericalProjector(options).project(cloud, one);
  options.threads = 3;
  SphericalProjector projector(options);
  for (int run = 0; run < 2; ++run) {
    projector.project(cloud, three);
    EXPECT_EQ(cv::norm(one.count, three.count, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(one.index, three.index, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(one.range, three.range, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(one.intensity, three.intensity, cv::NORM_INF), 0);
    EXPECT_EQ(one.points_projected, three.points_projected);
  }
  EXPECT_GT(one.points_projected, 60000u);
}

TEST(PreprocessThreads, SplitRowsGiveTheOneThreadImages) {
  // PreprocessOptions::threads under ThreadSanitizer: the OS1-64 sweep in ring rows of 0.1 deg
  // columns, resampled to square pixels (rows repeated, the case where a part must not copy the
  // row above it), its rows split between three threads, with Otsu's threshold and a known one
  // after the intensity normalisation of the Ouster presets.
  const PointCloud& cloud = scans().scans[0].cloud;
  ProjectionOptions projection;
  projection.res_h_deg = 0.1;
  projection.rows = RowLayout::kRings;
  ProjectedImage image;
  SphericalProjector(projection).project(cloud, image);
  ASSERT_GE(image.intensity.total(), 3u * 65536u);
  for (const std::optional<double> threshold : {std::optional<double>(), std::optional(40.0)}) {
    PreprocessOptions options;
    options.threshold = threshold;
    if (threshold) options.normalise.mode = IntensityNormalisation::kRangeIncidence;
    PreprocessedImage one, three;
    preprocess(image, options, one);
    ASSERT_GT(one.gray.rows, 2 * image.intensity.rows);  // square pixels
    options.threads = 3;
    for (int run = 0; run < 2; ++run) {
      preprocess(image, options, three);
      EXPECT_EQ(cv::norm(one.gray, three.gray, cv::NORM_INF), 0);
      EXPECT_EQ(cv::norm(one.detect, three.detect, cv::NORM_INF), 0);
      EXPECT_EQ(cv::norm(one.valid, three.valid, cv::NORM_INF), 0);
      EXPECT_EQ(one.threshold, three.threshold);
      EXPECT_EQ(cv::norm(one.normalised, three.normalised, cv::NORM_INF), 0);
    }
  }
}

TEST(LiftThreads, MarkersLiftedOnThreadsGiveTheOneThreadResults) {
  // PipelineOptions::lift_threads: each marker's plane fit and pose on one of three threads (the
  // sweep holds 65k points, above the 32k below which lifting stays on one thread).
  for (int k = 0; k < 2; ++k) {
    const PointCloud& cloud = scans().scans[k].cloud;
    ASSERT_GE(cloud.size(), 32768u);
    Pipeline one(os1_options());
    const Outcome alone = outcome_of(one.process(cloud));
    ASSERT_GE(alone.ids.size(), 3u) << "scan " << k;
    PipelineOptions options = os1_options();
    options.lift_threads = 3;
    Pipeline three(options);
    for (int run = 0; run < 2; ++run) {
      const FrameResult& r = three.process(cloud);
      expect_identical(alone, outcome_of(r), k);
      for (const MarkerResult& m : r.markers) EXPECT_TRUE(m.T_lidar_marker) << "scan " << k;
    }
  }
}

TEST(LiftThreads, OneMarkersPointsGatheredOnThreadsGiveTheOneThreadResults) {
  // A single marker (the tag wall, 20 Mid-40 frames): its plane fit's points are gathered on the
  // lift's threads (PlaneFitOptions::threads), its 300 x 300 pixel box in two parts.
  const sim::SimResult scan = mid40_scan("tag-wall");
  PipelineOptions options = mid40_options();
  options.marker_size = 0.172;
  Pipeline one(options);
  const Outcome alone = outcome_of(one.process(scan.cloud));
  ASSERT_EQ(alone.ids.size(), 1u);
  options.lift_threads = 3;
  Pipeline three(options);
  for (int run = 0; run < 2; ++run)
    expect_identical(alone, outcome_of(three.process(scan.cloud)), 0);
}

TEST(DetectThreads, FamiliesDetectedOnThreadsGiveTheOneThreadResults) {
  // PipelineOptions::detect_threads: the paper's grid (35 tag36h11 and 4 DICT_4X4_50 markers, 20
  // Mid-40 frames) with three families asked for, each family's detector on one of two or three
  // threads, and the markers in the families' order whatever thread finished first.
  // ArUco's detector runs OpenCV's parallel loops, on TBB's pool, which ThreadSanitizer does not
  // see into: a worker reading an image the calling thread wrote looks like a race to it (one
  // thread or several). The pipeline's own threads are what this test is about.
  struct OpenCvOnOneThread {
    int before = cv::getNumThreads();
    OpenCvOnOneThread() { cv::setNumThreads(1); }
    ~OpenCvOnOneThread() { cv::setNumThreads(before); }
  } opencv_on_one_thread;
  const sim::SimResult scan = mid40_scan("paper-grid");
  PipelineOptions options = mid40_options();
  options.families = {"apriltag:tag36h11", "aruco:DICT_4X4_50", "apriltag:tag25h9"};
  Pipeline one(options);
  const FrameResult& r = one.process(scan.cloud);
  const Outcome alone = outcome_of(r);
  std::size_t aruco = 0;
  for (const MarkerResult& m : r.markers) aruco += m.detection.family == "aruco:DICT_4X4_50";
  ASSERT_GE(alone.ids.size(), 30u);
  ASSERT_GE(aruco, 3u);
  for (const int threads : {2, 3}) {
    options.detect_threads = threads;
    Pipeline split(options);
    for (int run = 0; run < 2; ++run)
      expect_identical(alone, outcome_of(split.process(scan.cloud)), threads);
  }
}

TEST(DetectThreads, RingCandidatesFoundBesideTheDetectorGiveTheOneThreadResults) {
  // One family on ring rows: its detector on one thread while the ring candidates' dark squares
  // are found on another (the OS1-64 sweeps of the "around" room).
  for (int k = 0; k < 2; ++k) {
    const PointCloud& cloud = scans().scans[k].cloud;
    Pipeline one(os1_options());
    const Outcome alone = outcome_of(one.process(cloud));
    ASSERT_GE(alone.ids.size(), 3u) << "scan " << k;
    PipelineOptions options = os1_options();
    options.detect_threads = 2;
    Pipeline two(options);
    for (int run = 0; run < 2; ++run) expect_identical(alone, outcome_of(two.process(cloud)), k);
  }
}

}  // namespace
}  // namespace iilfm
