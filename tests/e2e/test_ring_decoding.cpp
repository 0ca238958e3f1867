// Ring-sample decoding (docs/pipeline.md) on simulated spinning LiDARs: a VLP-16 reads a 1 m
// tag36h11 beyond the 3 m where the detectors stop; the issue-5 case (c) ArUco markers are kept
// when their rings confirm the id and corrected when the detector read a wrong one; no marker is
// made up on scenes without the families asked for; over sub-pixel placements the ring
// candidates find what the detectors miss.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <random>
#include <utility>

#include "../../src/ring_decoding.hpp"
#include "iilfm/eval/case.hpp"
#include "iilfm/eval/detection_range.hpp"
#include "iilfm/option_names.hpp"

namespace iilfm {
namespace {

// The range study's scan (tag_wall, footprint on, the seed's tilt and turn of the LiDAR) or, with
// `level`, the paper suite's ArUco set-up (LiDAR level, one sweep).
eval::SimulatedCase wall_case(const std::string& sensor, const std::string& family, int id,
                              double size, double distance, int seed, bool level) {
  eval::CaseSpec spec = eval::tag_wall_spec(sensor, distance, size);
  spec.scene_params.family = family;
  spec.scene_params.id = id;
  spec.physics.footprint = !level;
  if (!level) {
    std::mt19937 rng(static_cast<std::uint32_t>(seed));
    std::uniform_real_distribution<double> tilt(-1.0, 1.0);
    spec.lidar_rpy_deg = Vec3(0, tilt(rng), 2 * tilt(rng));
  }
  spec.frames = 1;
  return eval::simulate_case(spec, static_cast<std::uint64_t>(seed));
}

// A grid scene's scan (eval::grid_spec, footprint on) and the pipeline's options for it, with the
// scene's map.
std::pair<eval::SimulatedCase, PipelineOptions> grid_case(const std::string& sensor,
                                                          const std::string& family,
                                                          double distance, int seed,
                                                          bool on_column_grid = false) {
  eval::CaseSpec spec = eval::grid_spec(sensor, family, distance);
  spec.on_column_grid = on_column_grid;
  spec.physics.footprint = true;
  eval::SimulatedCase c = eval::simulate_case(spec, static_cast<std::uint64_t>(seed));
  PipelineOptions options = eval::pipeline_options_for(c, LiftMethod::kPlane);
  return {std::move(c), std::move(options)};
}

// Release builds run `release` seeds; unoptimised (sanitizer) builds, which simulate the beam
// footprint 20-40x slower, run `sanitizer`.
constexpr int seeds(int release, int sanitizer) {
#ifdef NDEBUG
  (void)sanitizer;
  return release;
#else
  (void)release;
  return sanitizer;
#endif
}

struct Counts {
  int found = 0, wrong = 0;
};

// Runs the default pipeline (optionally changed) on one case and adds up its score.
template <typename Change>
void score(const eval::SimulatedCase& c, Change change, Counts& counts) {
  PipelineOptions options = eval::range_pipeline_options(c, eval::RangeSettings::kIilfm);
  change(options);
  Pipeline pipeline(options);
  const eval::CaseScore s = eval::score_frame(pipeline.process(c.scan.cloud), c.scan.truth);
  counts.found += s.detected > 0;
  counts.wrong += s.wrong_ids + s.false_positives;
}

// The default pipeline on the range study's scans of a tag36h11 (id 0) of `size` m at `distance`
// m: the first seeds(10, 2) seeds of `order` (the sanitizer builds run the first two).
Counts tag36h11_found(const std::string& sensor, double size, double distance,
                      const std::array<int, 10>& order) {
  constexpr int kSeeds = seeds(10, 2);
  Counts counts;
  for (int k = 0; k < kSeeds; ++k)
    score(
        wall_case(sensor, "apriltag:tag36h11", 0, size, distance, order[k], false),
        [](PipelineOptions&) {}, counts);
  std::printf("%s, %g m tag36h11 at %g m: %d of %d found\n", sensor.c_str(), size, distance,
              counts.found, kSeeds);
  return counts;
}

// tag36h11_found over the first seeds(10, 2) seeds of `order`: at least `of_ten` found when all
// ten run, both when the sanitizer builds run two, and no wrong id or false positive.
void expect_tag36h11_found(const std::string& sensor, double size, double distance,
                           const std::array<int, 10>& order, int of_ten) {
  constexpr int kSeeds = seeds(10, 2);
  const Counts counts = tag36h11_found(sensor, size, distance, order);
  EXPECT_GE(counts.found, kSeeds == 10 ? of_ten : 2)
      << sensor << ", " << size << " m at " << distance << " m";
  EXPECT_EQ(counts.wrong, 0) << sensor << ", " << size << " m at " << distance << " m";
}

TEST(RingDecoding, Vlp16ReadsAOneMetreTag36h11BeyondThreeMetres) {
  constexpr int kSeeds = seeds(10, 2);
  Counts with, without;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const eval::SimulatedCase c = wall_case("vlp16", "apriltag:tag36h11", 0, 1.0, 4.5, seed, false);
    score(
        c, [](PipelineOptions& o) { o.ring_candidates = true; }, with);
    score(
        c, [](PipelineOptions& o) { o.ring_candidates = false; }, without);
  }
  std::printf("VLP-16, 1 m tag36h11 at 4.5 m: %d of %d found with ring candidates, %d without\n",
              with.found, kSeeds, without.found);
  // Measured over 10 seeds: 7 with (6 when only the tied placings' middle was read; 10 with
  // session 26's decoding), 0 without (the detectors stop at 3-3.5 m); seeds 1 and 2 are among
  // them.
  EXPECT_GE(with.found, kSeeds / 2);
  EXPECT_EQ(without.found, 0);
  EXPECT_EQ(with.wrong + without.wrong, 0);
}

// A 40 cm tag36h11 at 1.5 m on a VLP-16: the 2 deg rings cross about one cell row each, so
// either side of the square may lie anywhere between two rings and the fixed cells fit 100-150 of
// a candidate's placings equally well. Seeds 1 and 2 (pitch 0.86 deg) read 4 errors at those
// placings' middle; 34 of their 142 placings read id 0 with none, and no other id decodes at any.
TEST(RingDecoding, Vlp16ReadsAFortyCentimetreTag36h11AtOnePointFiveMetresAtEveryRingPhase) {
  constexpr int kSeeds = seeds(10, 2);
  Counts counts;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const eval::SimulatedCase c = wall_case("vlp16", "apriltag:tag36h11", 0, 0.4, 1.5, seed, false);
    const int before = counts.found;
    score(
        c, [](PipelineOptions&) {}, counts);
    if (seed <= 2) {
      EXPECT_EQ(counts.found, before + 1) << "seed " << seed;
    }
  }
  std::printf("VLP-16, 40 cm tag36h11 at 1.5 m: %d of %d found\n", counts.found, kSeeds);
  // Measured over 10 seeds: 10 (8 when only the middle placing was read).
  EXPECT_GE(counts.found, kSeeds - 1);
  EXPECT_EQ(counts.wrong, 0);
}

// A 1 m tag36h11 at 12 m on an OS1-64 at 1024 columns spans 13.6 columns, 1.7 a cell: too few for
// the detectors, enough for the ring reader, which places each sample at its own azimuth. The
// candidates take squares down to 1.5 detector-image pixels a cell (2 before: 3 of 30 seeds found,
// 21 of 30 now). The sanitizer builds run seeds 3 and 4, two of those found.
TEST(RingDecoding, Os1_64ReadsAOneMetreTag36h11AtTwelveMetresFromUnderTwoColumnsACell) {
  // Measured over seeds 1-10: 5 (3, 4, 5, 7 and 8), 10 with session 26's decoding; none with 2
  // pixels a cell.
  expect_tag36h11_found("os1-64", 1.0, 12.0, {3, 4, 1, 2, 5, 6, 7, 8, 9, 10}, 4);
}

// Where the rings cross one cell row in two, many placings of a candidate read their few fixed
// cells all right by luck, and none of them may decode, while placings that read more fixed cells,
// a couple wrong, read the code. Those near-best placings vote too when no tied one decodes
// (kNearTolerance). An OS1-64's 1 m tag at 14 m: seed 6 had 43 tied placings reading 24-30 fixed
// cells and other codes, and placings reading 44 of 46 fixed cells read id 0 from 20 bits. The
// sanitizer builds run seeds 6 and 2.
TEST(RingDecoding, NearBestPlacingsVoteWhereNoTiedOneDecodes) {
  // Measured over seeds 1-10: 9 (all but seed 1); 8 with the tied placings alone (not seed 6).
  expect_tag36h11_found("os1-64", 1.0, 14.0, {6, 2, 1, 3, 4, 5, 7, 8, 9, 10}, 9);
}

// A mapped id whose reading the family's limits accept (10 chance-match bits) but a candidate
// would not (12) is counted among the map's codes: an OS1-64's 40 cm tag at 5 m read from 24
// bits with no error has 12.8 bits against 587 codes, 11.2 once the choice among tied placings is
// paid for, and 20.4 against the one mapped id (seed 2). So is one read with an error that lies
// three bits further from every other code (seed 9: one error in 22 bits, the reading four bits
// from the next code, which lies three from id 0). The sanitizer builds run seeds 9 and 2.
TEST(RingDecoding, AMappedIdTheFamilyAcceptsNeedsItsCandidateBitsOnlyAmongTheMapsCodes) {
  // Measured over seeds 1-10: 10 since the candidates' sides are measured on the rings (9 before,
  // not 4); 8 asking for 2 t + 3 bits to the next code (not 9), 7 counting the family's
  // chance-match bits (not 2 either).
  expect_tag36h11_found("os1-64", 0.4, 5.0, {9, 2, 1, 3, 4, 5, 6, 7, 8, 10}, 9);
}

// A candidate's left and right sides come from the binary image, on pixel edges: an OS1-64's 40
// cm tag at 6 m spans 10.9 columns, 1.36 a cell, and the binary image's square 10 (seed 1: 512.5
// to 522.5, the print 512.2 to 523.1), which read id 0 with two errors, too close to other codes.
// Read again with the sides where the rings cross the mid level (523.2 on the right), it reads id
// 0 without an error. The sanitizer builds run seeds 1 and 2.
TEST(RingDecoding, CandidateSidesMeasuredOnTheRingsReadANarrowSquare) {
  // Measured over seeds 1-10: 9 (not 7); 8 with the binary image's sides alone (not 1 or 7).
  expect_tag36h11_found("os1-64", 0.4, 6.0, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 9);
}

// At 1.3-1.5 columns a cell, which columns fall in which cell flips within a fraction of a pixel,
// so a candidate's reading swings with where its left and right sides lie. An OS1-64's 1 m tag at
// 15 m spans 10.9 columns: seed 6's binary square, 511.5 to 522.5 (the print 511.7 to 522.5),
// reads id 0 from only 7.8 chance-match bits, and at the same top and bottom shifts with both
// sides half a pixel out from 21.0; seed 7's reads 8.8 bits, and 19.0 so moved. The eight
// readings with the sides moved pay log2(9) bits. The sanitizer builds run seeds 6 and 7.
TEST(RingDecoding, CandidateSidesMovedHalfAPixelReadAOneMetreTagAtFifteenMetres) {
  // Measured over seeds 1-10: 10 (8 before: not seeds 6 and 7).
  expect_tag36h11_found("os1-64", 1.0, 15.0, {6, 7, 1, 2, 3, 4, 5, 8, 9, 10}, 10);
}

// The same two scans through the decoder alone: its candidates decode id 0 with the sides moved,
// and nothing without.
TEST(RingDecoding, WithoutMovingTheSidesTheWeakCandidatesStayUndecoded) {
  for (const int seed : {6, 7}) {
    const eval::SimulatedCase c =
        wall_case("os1-64", "apriltag:tag36h11", 0, 1.0, 15.0, seed, false);
    const PipelineOptions options = eval::range_pipeline_options(c, eval::RangeSettings::kIilfm);
    Pipeline pipeline(options);
    const FrameResult& r = pipeline.process(c.scan.cloud);
    const cv::Mat& intensity = options.preprocess.normalise.mode != IntensityNormalisation::kNone
                                   ? r.preprocessed.normalised
                                   : r.image.intensity;
    const cv::Mat& binary = r.preprocessed.detect;
    for (const double step : {0.5, 0.0}) {
      detail::RingDecodeSettings settings;
      settings.candidate_side_step_px = step;
      const detail::RingDecoder decoder(options.families, settings, known_ids_of(options));
      const detail::RingDecoder::Quads quads =
          decoder.candidate_quads(binary, r.preprocessed.geometry, r.image);
      std::vector<Detection> decoded;
      decoder.decode_candidates(binary, r.preprocessed.geometry, r.image, intensity, quads, decoded,
                                nullptr);
      const bool id_0 =
          std::any_of(decoded.begin(), decoded.end(), [](const Detection& d) { return d.id == 0; });
      EXPECT_EQ(id_0, step > 0) << "seed " << seed << ", sides moved by " << step << " px";
      EXPECT_TRUE(
          std::all_of(decoded.begin(), decoded.end(), [](const Detection& d) { return d.id == 0; }))
          << "seed " << seed;
    }
  }
}

// An OS1-64's 1 m tag at 16 m (seed 3): 10 columns and 5 rings, its black square cut in two by
// white data cells and its lower corners cut by the last ring, so the two parts' hull is a
// hexagon a pixel and a half off its quad, and 9.3 detector pixels tall where 9.5 are asked of
// the width. Both allowed for (a hull within 2 pixels of its quad, a height a ring spacing
// short), it reads id 0.
TEST(RingDecoding, ATenPixelSquareWithCutCornersAndARowShortIsRead) {
  Counts counts;
  score(
      wall_case("os1-64", "apriltag:tag36h11", 0, 1.0, 16.0, 3, false), [](PipelineOptions&) {},
      counts);
  EXPECT_EQ(counts.found, 1);
  EXPECT_EQ(counts.wrong, 0);
}

// The same tag at 16 m in other seeds: 10 pixels wide and 8 tall in the binary image (seeds 9 and
// 10), whose box dark_quads now lets fall a ring spacing short of its width as read_quad does. The
// sanitizer builds run seeds 9 and 10.
TEST(RingDecoding, ASquareBoxARingShortIsACandidate) {
  // Measured over seeds 1-10: 7 (not seeds 4 and 7, which do not decode at their true corners,
  // nor 5, whose left border column is not dark); 5 with the box as tall as it is wide.
  expect_tag36h11_found("os1-64", 1.0, 16.0, {9, 10, 1, 2, 3, 6, 8, 4, 5, 7}, 7);
}

// An OS1-128's 1 m tag at 23 m, 14 columns and 7 rings: where a ring grazed the top edge, its
// mixed pixels join the black square to dark specks of the wall above, and the square's hull gets
// a fifth or sixth vertex that approxPolyDP keeps (seed 5: a corner cut 2.02 pixels deep; seed 9:
// a speck 4 pixels up). Four of the hull's vertices are the square. The sanitizer builds run seeds
// 5 and 1.
TEST(RingDecoding, ASquareWithASpeckJoinedToItsHullIsRead) {
  // Measured over seeds 1-10: 10; 9 before a side fitted 8 degrees off its opposite was also laid
  // parallel to it (not seed 9, whose left side is found up to two pixels in); 8 when the hull had
  // to reduce to four vertices (not seed 5 either).
  expect_tag36h11_found("os1-128", 1.0, 23.0, {5, 1, 2, 3, 4, 6, 7, 8, 9, 10}, 9);
}

// The same tag at 20 m (seed 1): the ring under the bottom border row grazed it, reading its left
// half white, and the bottom side fitted along the sloping outline turned 18 degrees from the top
// one; no placing of that quad read the fixed cells. The quad with the bottom side laid parallel
// to the top reads id 0. The sanitizer builds run seeds 1 and 3.
TEST(RingDecoding, AGrazedSideLaidParallelToItsOppositeIsRead) {
  // Measured over seeds 1-10: 8 (not seeds 2 and 8); 7 from the fitted quads alone (not seed 1).
  expect_tag36h11_found("os1-128", 1.0, 20.0, {1, 3, 2, 4, 5, 6, 7, 8, 9, 10}, 8);
}

// The near-best placings vote also where the tied ones decode, but too weakly for a candidate
// once the choice among them is paid for. An ULTRA Puck 5 m from a grid of 35 tag25h9 (seed 2,
// the map's ids known): the tied placings of id 20's square decoded it with fewer than 12
// chance-match bits, near-best ones more securely; 4 of the grid's markers were found before, 5
// now. The case was found in a scan with every ring fired at its column's azimuth, and is run so.
TEST(RingDecoding, NearBestPlacingsVoteWhereTheTiedOnesDecodeTooWeakly) {
  auto [c, options] = grid_case("ultrapuck", "apriltag:tag25h9", 5.0, 2, true);
  ASSERT_TRUE(options.map);
  options.families = {"apriltag:tag25h9", "apriltag:tag36h11"};
  Pipeline pipeline(options);
  const FrameResult& r = pipeline.process(c.scan.cloud);
  const eval::CaseScore s = eval::score_frame(r, c.scan.truth);
  const bool found_20 = std::any_of(r.markers.begin(), r.markers.end(), [](const MarkerResult& m) {
    return m.detection.family == "apriltag:tag25h9" && m.detection.id == 20;
  });
  EXPECT_TRUE(found_20);
  EXPECT_GE(s.detected, 5);
  EXPECT_EQ(s.wrong_ids + s.false_positives, 0);
}

// A candidate's top and bottom sides come from the binary image, whose rows between rings are
// invented: they may lie up to half a ring spacing off the square, which on an ULTRA Puck's coarse
// outer rings is a few centimetres. The reported corners are those of the placing where the fixed
// cells read best. A 1 m tag36h11 at 3 m (only the candidates find it), seeds 1-10: corners
// 20.0 mm off at the median (38.0 at most) from the binary image's sides, 7.2 (17.5) now; a
// LiDAR pose in 6 scans (the corners' misfit to the square refused it in the others), now in 10.
TEST(RingDecoding, CandidateCornersLieWhereTheFixedCellsReadBest) {
  constexpr int kSeeds = seeds(10, 2);
  int found = 0, poses = 0;
  double corner_error = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const eval::SimulatedCase c =
        wall_case("ultrapuck", "apriltag:tag36h11", 0, 1.0, 3.0, seed, false);
    PipelineOptions options = eval::range_pipeline_options(c, eval::RangeSettings::kIilfm);
    Pipeline pipeline(options);
    const eval::CaseScore s = eval::score_frame(pipeline.process(c.scan.cloud), c.scan.truth);
    EXPECT_EQ(s.wrong_ids + s.false_positives, 0) << "seed " << seed;
    if (s.detected == 0) continue;
    ++found;
    poses += s.pose ? 1 : 0;
    corner_error += s.corner_error_mean;
  }
  ASSERT_EQ(found, kSeeds);
  corner_error /= found;
  std::printf("ULTRA Puck, 1 m tag36h11 at 3 m: corners %.1f mm off on average, %d poses\n",
              corner_error * 1000, poses);
  // Measured with the VLP-32C's lasers at their azimuth offsets: 9.0 mm on average over seeds 1-10
  // and 15.6 over seeds 1-2, the sanitizer builds' (9.1 and 15.5 with the offsets ignored; 8.0
  // and 12.4 with every ring on the column grid; 21.1 and 30.0 before the placings).
  EXPECT_LT(corner_error, kSeeds >= 10 ? 0.015 : 0.02);
  EXPECT_EQ(poses, kSeeds);
}

// Issue 5 case (c): a 40 cm DICT_ARUCO_ORIGINAL id 100 on a level VLP-16 Hi-Res at 1.5 m and a
// VLP-16 at 1 m, 1.6 rings per cell. The detectors decode the Hi-Res one right and the VLP-16 one
// as id 96 from the rows invented between rings; two rows per cell refused both.
TEST(RingDecoding, ArucoOriginalAtOnePointSixRingsPerCellIsKeptOrCorrected) {
  constexpr int kSeeds = 3;
  for (const auto& [sensor, distance] : {std::pair{"vlp16-hires", 1.5}, std::pair{"vlp16", 1.0}}) {
    Counts ring, rule, raw;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const eval::SimulatedCase c =
          wall_case(sensor, "aruco:DICT_ARUCO_ORIGINAL", 100, 0.4, distance, seed, true);
      score(
          c, [](PipelineOptions&) {}, ring);
      score(
          c, [](PipelineOptions& o) { o.ring_decode = false; }, rule);
      score(
          c,
          [](PipelineOptions& o) {
            o.ring_decode = false;
            o.min_samples_per_cell = 0;
          },
          raw);
    }
    SCOPED_TRACE(sensor);
    EXPECT_EQ(ring.found, kSeeds);  // measured 10 of 10 for both over 10 seeds
    EXPECT_EQ(ring.wrong, 0);
    EXPECT_EQ(rule.found, 0);
    if (std::string(sensor) == "vlp16") {
      EXPECT_EQ(raw.wrong, kSeeds);  // the detector alone: id 96 every time
    } else {
      EXPECT_EQ(raw.found, kSeeds);
    }
  }
}

// The issue-5 case (c) marker over sub-pixel placements (each seed turns the LiDAR by a random
// fraction of a column and of a ring): which cells the 1.33 deg rings cross now changes from
// seed to seed, and the detectors with the ring check miss the marker where the rings fall near
// cell edges. The candidates read it from the rings.
TEST(RingDecoding, ArucoOriginalOnAVlp16HiResIsFoundAtAnyRingPhase) {
  constexpr int kSeeds = seeds(10, 3);
  for (const double distance : {1.5, 2.0}) {
    Counts with, without;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      eval::CaseSpec spec = eval::tag_wall_spec("vlp16-hires", distance, 0.4);
      spec.scene_params.family = "aruco:DICT_ARUCO_ORIGINAL";
      spec.scene_params.id = 100;
      spec.frames = 1;
      spec.jitter_px = 1;
      const eval::SimulatedCase c = eval::simulate_case(spec, static_cast<std::uint64_t>(seed));
      score(
          c, [](PipelineOptions&) {}, with);
      score(
          c, [](PipelineOptions& o) { o.ring_candidates = false; }, without);
    }
    std::printf(
        "VLP-16 Hi-Res, 40 cm ARUCO_ORIGINAL at %.1f m: %d of %d found, %d without the "
        "candidates\n",
        distance, with.found, kSeeds, without.found);
    SCOPED_TRACE(distance);
    // Measured over seeds 1-10: 10 and 9 of 10 found at 1.5 and 2 m (10 and 10 with session
    // 26's decoding), 2 and 0 without.
    EXPECT_GE(with.found, kSeeds - 2);
#ifdef NDEBUG
    EXPECT_GT(with.found, without.found);
#endif
    EXPECT_EQ(with.wrong + without.wrong, 0);
  }
}

// Markers of other families are dark squares too: asked for tag36h11, tag25h9 and the original
// ArUco dictionary, the stage must not decode a tag16h5 or a DICT_4X4_50 marker as one of them,
// at any distance from where the detectors read them to where only a blob is left.
TEST(RingDecoding, OtherFamiliesSquaresAreNotDecoded) {
  constexpr int kSeeds = seeds(50, 4);
  const char* sensors[] = {"vlp16", "vlp16-hires", "os1-64"};
  const char* families[] = {"apriltag:tag16h5", "aruco:DICT_4X4_50"};
  int made_up = 0, scans = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const char* sensor = sensors[seed % 3];
    const char* family = families[seed % 2];
    const double distance = 1.5 + 0.1 * seed;  // 1.6-6.5 m
    const double size = seed % 4 < 2 ? 0.4 : 1.0;
    const eval::SimulatedCase c = wall_case(sensor, family, seed % 20, size, distance, seed, false);
    PipelineOptions options = eval::range_pipeline_options(c, eval::RangeSettings::kIilfm);
    options.families = {"apriltag:tag36h11", "apriltag:tag25h9", "aruco:DICT_ARUCO_ORIGINAL"};
    options.map.reset();
    Pipeline pipeline(options);
    const FrameResult& r = pipeline.process(c.scan.cloud);
    made_up += static_cast<int>(r.markers.size());
    ++scans;
    for (const MarkerResult& m : r.markers)
      ADD_FAILURE() << sensor << " seed " << seed << ": " << family << " read as "
                    << m.detection.family << " id " << m.detection.id;
  }
  EXPECT_EQ(made_up, 0);
  EXPECT_EQ(scans, kSeeds);
}

// Every family asked for is one more chance for a square to match some code. A 35-marker
// DICT_4X4_50 grid 4 m from an ULTRA Puck, seven families asked for: one of its squares read
// through the 7 x 7 cells of the original ArUco dictionary matched id 193 on 24 of 25 bits, which
// is the 12 chance-match bits a single family's candidate needs, until each family whose fixed
// cells fit the square counted as one more try.
TEST(RingDecoding, EachFamilyAskedForIsAnotherChanceForACandidate) {
  const eval::SimulatedCase c =
      eval::simulate_case(eval::grid_spec("ultrapuck", "aruco:DICT_4X4_50", 4.0), 2);
  PipelineOptions options = eval::range_pipeline_options(c, eval::RangeSettings::kIilfm);
  options.families = {"apriltag:tag36h11",         "apriltag:tag25h9",  "apriltag:tag16h5",
                      "aruco:DICT_ARUCO_ORIGINAL", "aruco:DICT_4X4_50", "aruco:DICT_5X5_100",
                      "apriltag:tagStandard41h12"};
  options.map.reset();
  Pipeline pipeline(options);
  const eval::CaseScore s = eval::score_frame(pipeline.process(c.scan.cloud), c.scan.truth);
  EXPECT_EQ(s.wrong_ids + s.false_positives, 0);
}

// The map says which ids are in the scene, so a reading whose nearest code is a mapped id needs
// its chance-match bits only among the mapped codes (9 bits fewer for one tag36h11 id). A VLP-16's
// rings cross a 1 m tag at 5 m in about five places, leaving 24-30 of its 36 bits: too few for
// 587 ids, enough for one. The sanitizer builds run seeds 3 and 4, which only the map finds.
TEST(RingDecoding, TheMapsIdsAreReadFromFewerRings) {
  constexpr int kSeeds = seeds(10, 2);
  const int order[10] = {3, 4, 1, 2, 5, 6, 7, 8, 9, 10};
  Counts with_map, without_map;
  for (int k = 0; k < kSeeds; ++k) {
    const eval::SimulatedCase c =
        wall_case("vlp16", "apriltag:tag36h11", 0, 1.0, 5.0, order[k], false);
    score(
        c, [](PipelineOptions&) {}, with_map);
    score(
        c, [](PipelineOptions& o) { o.map.reset(); }, without_map);
  }
  std::printf("VLP-16, 1 m tag36h11 at 5 m: %d of %d found with its map, %d without\n",
              with_map.found, kSeeds, without_map.found);
  // Measured over seeds 1-10: 9 with the map (10 with session 26's decoding), 2 without (seeds 1
  // and 2).
  EXPECT_GE(with_map.found, kSeeds == 10 ? 8 : 2);
  EXPECT_LE(without_map.found, kSeeds == 10 ? 3 : 0);
  EXPECT_EQ(with_map.wrong + without_map.wrong, 0);
}

// `--ids` without a map: the ids given are known, as a map's are, so they too are read from
// fewer rings; markers of other ids are not reported. The sanitizer builds run seeds 3 and 4.
TEST(RingDecoding, IdsGivenAreReadFromFewerRingsAndAloneReported) {
  constexpr int kSeeds = seeds(10, 2);
  const int order[10] = {3, 4, 1, 2, 5, 6, 7, 8, 9, 10};
  Counts given;
  for (int k = 0; k < kSeeds; ++k) {
    const eval::SimulatedCase c =
        wall_case("vlp16", "apriltag:tag36h11", 0, 1.0, 5.0, order[k], false);
    score(
        c,
        [](PipelineOptions& o) {
          o.map.reset();
          set_known_ids({0}, o);
        },
        given);
  }
  std::printf("VLP-16, 1 m tag36h11 at 5 m: %d of %d found with --ids 0\n", given.found, kSeeds);
  // Measured over seeds 1-10: 9, 10 with session 26's decoding (2 with neither ids nor map,
  // TheMapsIdsAreReadFromFewerRings; 4 with --ids 0,1,2: each id known is one more code a random
  // reading may match).
  EXPECT_GE(given.found, kSeeds == 10 ? 8 : 2);
  EXPECT_EQ(given.wrong, 0);

  // Up close every detector finds the tag; told the scene holds ids 1 and 2, none reports it.
  const eval::SimulatedCase near = wall_case("vlp16", "apriltag:tag36h11", 0, 1.0, 2.5, 1, false);
  Counts all_ids, other_ids;
  score(
      near, [](PipelineOptions&) {}, all_ids);
  score(
      near,
      [](PipelineOptions& o) {
        o.map.reset();
        set_known_ids({1, 2}, o);
      },
      other_ids);
  EXPECT_EQ(all_ids.found, 1);
  EXPECT_EQ(other_ids.found + other_ids.wrong, 0);
}

// A map that lists only some of the markers in view: the others must not be read as listed ids.
// An ARUCO_ORIGINAL grid 5 m from a VLP-16 Hi-Res, mapped ids 0, 7, ..., 28 of 35: one unlisted
// marker read from 17 bits matched mapped id 0 with no error, and another code two bits away,
// until a known id needed three bits to every other code (FamilyCodeBooks::decode).
TEST(RingDecoding, APartialMapDoesNotTurnUnlistedMarkersIntoListedOnes) {
  auto [c, options] = grid_case("vlp16-hires", "aruco:DICT_ARUCO_ORIGINAL", 5.0, 2);
  ASSERT_TRUE(options.map);
  MarkerMap listed;
  for (const MapMarker& m : options.map->markers())
    if (m.id % 7 == 0) listed.add(m);
  options.map = listed;
  options.families = {"aruco:DICT_ARUCO_ORIGINAL", "apriltag:tag36h11"};
  Pipeline pipeline(options);
  const eval::CaseScore s = eval::score_frame(pipeline.process(c.scan.cloud), c.scan.truth);
  EXPECT_EQ(s.wrong_ids + s.false_positives, 0);
}

}  // namespace
}  // namespace iilfm
