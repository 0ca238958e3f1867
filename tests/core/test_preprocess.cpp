#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/preprocess.hpp"
#include "iilfm/square_pixels.hpp"

namespace iilfm {
namespace {

// `rows` x `cols` pixels, every one observed, of one intensity and range.
ProjectedImage uniform_image(int rows, int cols, float intensity, float range) {
  ProjectedImage img;
  img.intensity = cv::Mat(rows, cols, CV_32F, cv::Scalar(intensity));
  img.mask = cv::Mat(rows, cols, CV_8U, cv::Scalar(255));
  img.range = cv::Mat(rows, cols, CV_32F, cv::Scalar(range));
  return img;
}

// A 20x20 image: left half intensity 10 (black print), right half 120 (white), one hole in each.
ProjectedImage two_tone() {
  ProjectedImage img = uniform_image(20, 20, 10, 2);
  img.intensity.colRange(10, 20).setTo(120);
  for (auto [r, c] : {std::pair{5, 4}, std::pair{12, 15}}) {
    img.intensity.at<float>(r, c) = 0;
    img.mask.at<uchar>(r, c) = 0;
  }
  return img;
}

TEST(Preprocess, NaiveThresholdBinarisesAndFillsHolesFromNeighbours) {
  PreprocessOptions opt;
  opt.threshold = 60;
  PreprocessedImage out;
  preprocess(two_tone(), opt, out);
  EXPECT_EQ(out.threshold, 60);
  EXPECT_EQ(out.detect.at<uchar>(3, 3), 0);
  EXPECT_EQ(out.detect.at<uchar>(3, 16), 255);
  EXPECT_EQ(out.detect.at<uchar>(5, 4), 0);      // hole in black stays black
  EXPECT_EQ(out.detect.at<uchar>(12, 15), 255);  // hole in white is white
  EXPECT_EQ(out.gray.at<uchar>(3, 16), 128);     // the 99th percentile maps to half of 255
}

// A dim checkerboard (black 5, white 30: far, or dark paper) beside a bright wall (120): the global
// threshold 40 makes the whole board black; the local one keeps its cells and leaves the flat
// wall to the global threshold.
TEST(Preprocess, LocalThresholdKeepsADimPatternAndLeavesFlatRegionsGlobal) {
  ProjectedImage img = uniform_image(40, 80, 120, 2);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) img.intensity.at<float>(r, c) = ((r / 5 + c / 5) % 2) ? 30 : 5;
  PreprocessOptions opt;
  opt.threshold = 40;
  PreprocessedImage global, local;
  preprocess(img, opt, global);
  opt.local_threshold = true;
  preprocess(img, opt, local);
  const cv::Rect board(0, 0, 40, 40), wall(50, 0, 30, 40);
  EXPECT_EQ(cv::countNonZero(global.detect(board)), 0);
  // About half the board's cells white (those whose window spans both levels), the wall white.
  const int white = cv::countNonZero(local.detect(board));
  EXPECT_GT(white, 40 * 40 * 4 / 10);
  EXPECT_LT(white, 40 * 40 * 6 / 10);
  EXPECT_EQ(local.detect.at<uchar>(12, 7), 255);  // a 30 cell
  EXPECT_EQ(local.detect.at<uchar>(12, 12), 0);   // a 5 cell
  EXPECT_EQ(cv::countNonZero(local.detect(wall)), 30 * 40);
}

TEST(Preprocess, UnfilledHolesTakeTheUnobservedValue) {
  PreprocessOptions opt;
  opt.threshold = 60;
  opt.fill_holes = false;
  opt.hole_class_block = 0;
  opt.unobserved_value = 77;
  PreprocessedImage out;
  preprocess(two_tone(), opt, out);
  EXPECT_EQ(out.detect.at<uchar>(12, 15), 77);
  EXPECT_EQ(out.gray.at<uchar>(5, 4), 77);
}

// Holes that filling cannot close (under 3 observed neighbours): a sparse scan's gaps. In the
// binary image they take the class of the observed pixels around them: white on the white wall,
// black on the dark floor, white where nothing around is observed (no edge for the detectors).
TEST(Preprocess, UnfillableHolesTakeTheClassOfTheirSurroundings) {
  ProjectedImage img;
  img.intensity = cv::Mat(40, 60, CV_32F, cv::Scalar(120));  // wall
  img.intensity.rowRange(20, 40).setTo(10);                  // floor
  img.mask = cv::Mat(40, 60, CV_8U, cv::Scalar(0));
  img.range = cv::Mat(40, 60, CV_32F, cv::Scalar(2));
  // Every third row and column observed (no hole has the 3 observed neighbours filling needs),
  // nothing right of column 44.
  for (int r = 0; r < 40; r += 3)
    for (int c = 0; c < 45; c += 3) img.mask.at<uchar>(r, c) = 255;
  PreprocessOptions opt;
  opt.threshold = 60;
  PreprocessedImage out;
  preprocess(img, opt, out);
  const cv::Mat holes = out.valid == 0;
  ASSERT_GT(cv::countNonZero(holes), 40 * 60 / 2)
      << "filling closed the gaps: the test checks too little";
  EXPECT_EQ(out.detect.at<uchar>(4, 10), 255);   // a hole on the wall
  EXPECT_EQ(out.detect.at<uchar>(34, 10), 0);    // on the floor
  EXPECT_EQ(out.detect.at<uchar>(10, 57), 255);  // no observation near
  EXPECT_EQ(out.detect.at<uchar>(31, 57), 255);
  // The observed pixels keep their own class.
  EXPECT_EQ(out.detect.at<uchar>(3, 3), 255);
  EXPECT_EQ(out.detect.at<uchar>(33, 3), 0);
  // The local threshold's holes too (they were all black: streaks across a sparse Livox image).
  opt.local_threshold = true;
  preprocess(img, opt, out);
  EXPECT_EQ(out.detect.at<uchar>(4, 10), 255);
  EXPECT_EQ(out.detect.at<uchar>(34, 10), 0);
  EXPECT_EQ(out.detect.at<uchar>(10, 57), 255);
  opt.local_threshold = false;
  opt.hole_class_block = 0;  // the constant instead
  preprocess(img, opt, out);
  EXPECT_EQ(out.detect.at<uchar>(4, 10), 0);
}

// Every hole against a direct count: the observed pixels of its block and the 8 around (blocks
// at the image's edges cut short, odd sizes, several block sizes up to the largest, one buffer
// reused across sizes), majority white or nothing observed gives white.
TEST(Preprocess, HoleClassesMatchADirectCountOfTheBlocksAround) {
  constexpr int kRows = 137, kCols = 153;
  std::mt19937 rng(5);
  std::bernoulli_distribution seen(0.08), light(0.5);
  ProjectedImage img;
  img.intensity = cv::Mat(kRows, kCols, CV_32F, cv::Scalar(0));
  img.mask = cv::Mat(kRows, kCols, CV_8U, cv::Scalar(0));
  img.range = cv::Mat(kRows, kCols, CV_32F, cv::Scalar(2));
  // Stripes of rows observed throughout: bands without a hole next to bands with holes, whose
  // classes count the stripes' pixels.
  const auto whole_row = [&](int r) {
    return (r >= 30 && r < 60) || (r >= 100 && r < 104) || r > 133;
  };
  for (int r = 0; r < kRows; ++r) {
    for (int c = 0; c < kCols; ++c) {
      if (!whole_row(r) && !seen(rng)) continue;
      img.mask.at<uchar>(r, c) = 255;
      // Whiter on the right, so blocks of every class and ties occur.
      img.intensity.at<float>(r, c) = light(rng) || c > 100 ? 120.0f : 10.0f;
    }
  }
  PreprocessedImage out;
  for (const int block : {2, 3, 1, 5, 64, 2}) {
    PreprocessOptions opt;
    opt.threshold = 60;
    opt.hole_class_block = block;
    preprocess(img, opt, out);
    // Counts of observed and of observed white pixels over any rectangle, from integral images.
    cv::Mat observed_sum, white_sum;
    cv::integral(out.valid / 255, observed_sum, CV_32S);
    cv::integral((out.valid & out.detect) / 255, white_sum, CV_32S);  // observed: its own class
    const auto sum = [](const cv::Mat& s, int y0, int x0, int y1, int x1) {
      return s.at<int>(y1, x1) - s.at<int>(y0, x1) - s.at<int>(y1, x0) + s.at<int>(y0, x0);
    };
    int holes = 0;
    for (int r = 0; r < kRows; ++r) {
      for (int c = 0; c < kCols; ++c) {
        if (out.valid.at<uchar>(r, c)) continue;
        ++holes;
        // The rows and columns of the pixel's block and its neighbours, cut at the image's edges.
        const int y0 = std::max(0, (r / block - 1) * block);
        const int y1 = std::min(kRows, (r / block + 2) * block);
        const int x0 = std::max(0, (c / block - 1) * block);
        const int x1 = std::min(kCols, (c / block + 2) * block);
        const int observed = sum(observed_sum, y0, x0, y1, x1);
        const int white = sum(white_sum, y0, x0, y1, x1);
        const int expected = observed == 0 || 2 * white > observed ? 255 : 0;
        ASSERT_EQ(out.detect.at<uchar>(r, c), expected)
            << "block " << block << ", hole (" << r << ", " << c << ")";
      }
    }
    EXPECT_GT(holes, kRows * kCols / 2) << "filling closed the gaps: the test checks too little";
  }
  PreprocessOptions too_large;
  too_large.threshold = 60;
  too_large.hole_class_block = 65;
  EXPECT_THROW(preprocess(img, too_large, out), InputError);
}

// Hole filling against its definition, pixel by pixel: an unobserved pixel with at least 3
// observed of its 8 neighbours takes their mean (summed column by column, top to bottom, then left
// to right, as the pass adds them), the others keep their value or none. On ring-row images the
// pass skips uniform 32-pixel blocks; both ways must give these floats. The scenes have observed
// and empty stretches of every length around the blocks' edges, whole observed rows, sparse
// patches, and unobserved pixels holding values that must not leak.
TEST(Preprocess, FilledHolesAreTheMeanOfTheirObservedNeighboursInBlocksOrNot) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> level(0, 200);
  std::uniform_int_distribution<int> stretch(1, 300);
  const auto one_pass = [](const cv::Mat& v, const cv::Mat& m, cv::Mat& out, cv::Mat& out_mask) {
    out.create(v.size(), CV_32F);
    out_mask.create(v.size(), CV_8U);
    const auto at = [&](int r, int c, bool value) -> float {
      if (r < 0 || c < 0 || r >= v.rows || c >= v.cols || !m.at<uchar>(r, c)) return 0.0f;
      return value ? v.at<float>(r, c) : 1.0f;
    };
    for (int r = 0; r < v.rows; ++r)
      for (int c = 0; c < v.cols; ++c) {
        float sum = 0, count = 0;
        for (int dc = -1; dc <= 1; ++dc) {
          sum += at(r - 1, c + dc, true) + at(r, c + dc, true) + at(r + 1, c + dc, true);
          count += at(r - 1, c + dc, false) + at(r, c + dc, false) + at(r + 1, c + dc, false);
        }
        const bool observed = m.at<uchar>(r, c) != 0, fillable = count >= 2.5f;
        out.at<float>(r, c) = observed   ? v.at<float>(r, c)
                              : fillable ? sum / std::max(count, 1.0f)
                                         : 0;
        out_mask.at<uchar>(r, c) = observed || fillable ? 255 : 0;
      }
  };
  int skippable = 0;
  for (int trial = 0; trial < 12; ++trial) {
    ProjectedImage img;
    const int rows = 8 + trial % 5 * 7, cols = 300 + 53 * trial;
    img.intensity = cv::Mat(rows, cols, CV_32F);
    img.mask = cv::Mat(rows, cols, CV_8U);
    img.range = cv::Mat(rows, cols, CV_32F, cv::Scalar(5));
    // Rows of stretches observed, empty or sparse, of random lengths; most rows repeat the row
    // above, so edges line up over the three rows a pixel's neighbours span.
    for (int r = 0; r < rows; ++r) {
      if (r > 0 && rng() % 10 < 7) {
        img.mask.row(r - 1).copyTo(img.mask.row(r));
      } else {
        for (int c = 0; c < cols;) {
          const int kind = static_cast<int>(rng() % 3), end = std::min(cols, c + stretch(rng));
          for (; c < end; ++c)
            img.mask.at<uchar>(r, c) = kind == 0 || (kind == 2 && rng() % 4 == 0) ? 255 : 0;
        }
      }
      for (int c = 0; c < cols; ++c)  // unobserved pixels hold values never to be read
        img.intensity.at<float>(r, c) = img.mask.at<uchar>(r, c) ? level(rng) : 1e6f;
    }
    cv::Mat pass1, mask1, expected, expected_mask;
    one_pass(img.intensity, img.mask, pass1, mask1);
    one_pass(pass1, mask1, expected, expected_mask);
    for (bool rings : {false, true}) {
      img.geometry = ImageGeometry{};
      img.geometry.width = cols;
      img.geometry.height = rows;
      img.geometry.res_h = img.geometry.res_v = 0.01;
      if (rings)  // ring rows 0.01 rad apart, as fine as the columns: no square pixels needed
        for (int r = 0; r < rows; ++r) img.geometry.row_elevation.push_back(0.1 - 0.01 * r);
      PreprocessOptions opt;
      opt.threshold = 100;
      opt.square_pixels = false;
      PreprocessedImage out;
      preprocess(img, opt, out);
      const PreprocessedImage::Buffers& filled = out.work[1];  // the second pass's output
      ASSERT_EQ(cv::norm(filled.values, expected, cv::NORM_INF), 0) << "trial " << trial << rings;
      ASSERT_EQ(cv::norm(filled.mask, expected_mask, cv::NORM_INF), 0)
          << "trial " << trial << rings;
    }
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c + 32 <= cols; c += 32)
        skippable += cv::countNonZero(img.mask.row(r).colRange(c, c + 32)) % 32 == 0;
  }
  EXPECT_GT(skippable, 200);  // blocks wholly observed or empty, for the block pass to skip
}

TEST(Preprocess, OtsuSplitsTheTwoLevels) {
  PreprocessOptions opt;  // no threshold: Otsu
  PreprocessedImage out;
  preprocess(two_tone(), opt, out);
  EXPECT_GT(out.threshold, 10);
  EXPECT_LT(out.threshold, 120);
  EXPECT_EQ(out.detect.at<uchar>(3, 3), 0);
  EXPECT_EQ(out.detect.at<uchar>(3, 16), 255);
}

// The two-tone image with its intensity scaled from 0..255 to 0..1 (reflectance as KITTI's files
// and many conversions hold it) against a preset's threshold of 40.
ProjectedImage two_tone_in_unit_scale() {
  ProjectedImage img = two_tone();
  img.intensity /= 255.0;
  return img;
}

TEST(Preprocess, ThresholdAboveEveryIntensityIsReplacedByOtsus) {
  PreprocessOptions opt;
  opt.threshold = 40;
  PreprocessedImage out;
  preprocess(two_tone_in_unit_scale(), opt, out);
  ASSERT_TRUE(out.replaced_threshold.has_value());
  EXPECT_EQ(*out.replaced_threshold, 40);
  EXPECT_TRUE(out.threshold_above_all);
  EXPECT_FLOAT_EQ(out.max_intensity, 120 / 255.0);
  EXPECT_GT(out.threshold, 10 / 255.0);  // Otsu's, between the two levels
  EXPECT_LT(out.threshold, 120 / 255.0);
  EXPECT_EQ(out.detect.at<uchar>(3, 3), 0);
  EXPECT_EQ(out.detect.at<uchar>(3, 16), 255);
}

TEST(Preprocess, ThresholdTheUserGaveIsKeptEvenAboveEveryIntensity) {
  PreprocessOptions opt;
  opt.threshold = 40;
  opt.replace_threshold_above_all = false;
  PreprocessedImage out;
  preprocess(two_tone_in_unit_scale(), opt, out);
  EXPECT_FALSE(out.replaced_threshold.has_value());
  EXPECT_TRUE(out.threshold_above_all);  // reported, so the CLI can warn
  EXPECT_EQ(out.threshold, 40);
  EXPECT_EQ(out.detect.at<uchar>(3, 16), 0);  // nothing is white
}

TEST(Preprocess, ThresholdBelowSomeIntensityIsKeptInADarkImage) {
  // A dark scene: 99 % of the pixels below the threshold, but one white pixel above it.
  ProjectedImage img = uniform_image(20, 20, 10, 2);
  img.intensity.at<float>(7, 7) = 90;
  PreprocessOptions opt;
  opt.threshold = 40;
  PreprocessedImage out;
  preprocess(img, opt, out);
  EXPECT_FALSE(out.replaced_threshold.has_value());
  EXPECT_FALSE(out.threshold_above_all);
  EXPECT_EQ(out.threshold, 40);
  EXPECT_EQ(out.detect.at<uchar>(7, 7), 255);
}

TEST(Preprocess, CloudWithoutIntensityIsSaidToCarryNone) {
  // Every intensity 0 (a cloud without an intensity field), with a preset's threshold and with
  // Otsu's: no threshold can show a marker, and nothing is replaced.
  for (const std::optional<double> threshold :
       {std::optional<double>(40), std::optional<double>()}) {
    PreprocessOptions opt;
    opt.threshold = threshold;
    PreprocessedImage out;
    preprocess(uniform_image(20, 20, 0, 2), opt, out);
    EXPECT_TRUE(out.no_intensity);
    EXPECT_FALSE(out.replaced_threshold.has_value());
  }
  PreprocessedImage lit;
  preprocess(two_tone(), PreprocessOptions{}, lit);
  EXPECT_FALSE(lit.no_intensity);
}

TEST(Preprocess, GrayModeKeepsLevels) {
  PreprocessOptions opt;
  opt.binarize = false;
  PreprocessedImage out;
  preprocess(two_tone(), opt, out);
  EXPECT_NEAR(out.detect.at<uchar>(3, 3), 10 * 255 / 240, 1);  // 255 at twice the percentile
}

// A wall filling the image (60) with a small marker on it (black 5, white paper 90, 0.5 % of the
// pixels each): the paper keeps its own gray level above the wall's. With the percentile itself
// as 255, the wall was the percentile and paper and wall were both 255.
TEST(Preprocess, WhitePaperBrighterThanTheWallIsNotClipped) {
  ProjectedImage img = uniform_image(100, 200, 60, 5);
  img.intensity(cv::Rect(10, 10, 10, 10)).setTo(90);
  img.intensity(cv::Rect(20, 10, 10, 10)).setTo(5);
  PreprocessOptions opt;
  opt.threshold = 40;
  PreprocessedImage out;
  preprocess(img, opt, out);
  const int wall = out.gray.at<uchar>(50, 100), paper = out.gray.at<uchar>(15, 15);
  const int black = out.gray.at<uchar>(15, 25);
  EXPECT_LT(paper, 255);
  EXPECT_GT(paper, wall + 30);
  EXPECT_LT(black, 15);
}

// The gray scale is twice the 99th percentile of a sample of the image's own pixels, whatever
// came before: a large bright image (sampled sparsely, 16k of its 1.2 million pixels), then the
// small two-tone one (every pixel), then the large one again.
TEST(Preprocess, IntensityScaleComesFromTheImageAlone) {
  const ProjectedImage large = uniform_image(1100, 1100, 400, 2);
  PreprocessOptions opt;
  opt.threshold = 60;
  PreprocessedImage out;
  preprocess(large, opt, out);
  EXPECT_NEAR(out.intensity_scale, 800, 1e-3);
  preprocess(two_tone(), opt, out);
  EXPECT_NEAR(out.intensity_scale, 240, 1e-3);
  preprocess(large, opt, out);
  EXPECT_NEAR(out.intensity_scale, 800, 1e-3);
}

// Otsu's threshold over every observed pixel of `gray`, in gray levels (t + 0.5 for the split
// below and above level t): the textbook formula, for comparison.
double otsu_of_every_pixel(const cv::Mat& gray, const cv::Mat& valid) {
  std::vector<double> histogram(256, 0);
  for (int r = 0; r < gray.rows; ++r)
    for (int c = 0; c < gray.cols; ++c)
      if (valid.at<uchar>(r, c)) histogram[gray.at<uchar>(r, c)] += 1;
  double best = -1, best_t = 127.5;
  for (int t = 0; t < 255; ++t) {
    double below = 0, above = 0, sum_below = 0, sum_above = 0;
    for (int i = 0; i < 256; ++i) {
      (i <= t ? below : above) += histogram[i];
      (i <= t ? sum_below : sum_above) += i * histogram[i];
    }
    if (below == 0 || above == 0) continue;
    const double d = sum_below / below - sum_above / above;
    if (below * above * d * d > best) {
      best = below * above * d * d;
      best_t = t + 0.5;
    }
  }
  return best_t;
}

// Otsu's histogram skips runs of eight unobserved pixels at once (a Livox image's corners outside
// its circle, a single frame's gaps) and counts the rest without a branch: the threshold must be
// the textbook one over the observed pixels, with rows whose width is no multiple of eight.
TEST(Preprocess, OtsuOverASparseCircleIsTheTextbookOne) {
  constexpr int kSide = 301;
  PreprocessedImage image;
  image.gray = cv::Mat(kSide, kSide, CV_8U);
  image.valid = cv::Mat(kSide, kSide, CV_8U, cv::Scalar(0));
  image.repeats_row_above.assign(kSide, 0);
  image.intensity_scale = 2.0;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> any_level(0, 255);
  std::bernoulli_distribution seen(0.05), dark(0.3);
  int observed = 0;
  for (int r = 0; r < kSide; ++r)
    for (int c = 0; c < kSide; ++c) {
      // Unobserved pixels hold any level: only the mask may keep them out.
      image.gray.at<uchar>(r, c) = static_cast<uchar>(any_level(rng));
      const double from_centre = std::hypot(r - kSide / 2, c - kSide / 2);
      if (from_centre > kSide / 2 || !seen(rng)) continue;
      image.valid.at<uchar>(r, c) = 255;
      image.gray.at<uchar>(r, c) = static_cast<uchar>(dark(rng) ? 30 + r % 20 : 180 + c % 40);
      ++observed;
    }
  ASSERT_GT(observed, 2000);
  EXPECT_DOUBLE_EQ(otsu_threshold(image),
                   otsu_of_every_pixel(image.gray, image.valid) * image.intensity_scale / 255.0);
}

// A VLP-16 sweep's square-pixel image repeats most rows; preprocessing copies those rows and
// counts them once per copy in Otsu's histogram. The images and the threshold must be those of
// every row computed on its own.
TEST(Preprocess, RowsRepeatedBySquarePixelsGiveWhatEveryRowComputedGives) {
  constexpr double kDeg = M_PI / 180.0;
  ProjectedImage img;
  img.geometry = geometry_for_bounds({-0.6, 0.6, -15 * kDeg, 15 * kDeg}, 0.2 * kDeg, 2 * kDeg);
  const int rows = img.geometry.height, cols = img.geometry.width;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> level(0, 200);
  std::bernoulli_distribution seen(0.85);
  img.intensity = cv::Mat(rows, cols, CV_32F, cv::Scalar(0));
  img.mask = cv::Mat(rows, cols, CV_8U, cv::Scalar(0));
  img.range = cv::Mat(rows, cols, CV_32F, cv::Scalar(4));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (!seen(rng)) continue;
      img.mask.at<uchar>(r, c) = 255;
      img.intensity.at<float>(r, c) = level(rng) + (c % 40 < 20 ? 0.0f : 60.0f);
    }
  PreprocessOptions opt;  // Otsu, square pixels
  opt.fill_holes = false;
  opt.hole_class_block = 0;  // unobserved pixels keep `unobserved_value`
  PreprocessedImage out;
  preprocess(img, opt, out);

  const ImageGeometry square = square_pixel_geometry(img.geometry);
  cv::Mat values, valid;
  std::vector<std::uint8_t> repeats;
  resample_rows(img.intensity, img.mask, img.geometry, square, values, valid, &repeats);
  ASSERT_EQ(out.gray.size(), values.size());
  int repeated = 0;
  for (int r = 1; r < values.rows; ++r) {
    if (!repeats[static_cast<std::size_t>(r)]) continue;
    ++repeated;
    ASSERT_EQ(cv::norm(values.row(r), values.row(r - 1), cv::NORM_INF), 0) << r;
    ASSERT_EQ(cv::norm(valid.row(r), valid.row(r - 1), cv::NORM_INF), 0) << r;
  }
  EXPECT_GT(repeated, values.rows / 2) << "too few rows repeat: the test checks too little";

  // Gray level = intensity x 255 / scale, rounded half up, clamped to 0..255.
  const auto factor = static_cast<float>(255.0 / out.intensity_scale);
  cv::Mat gray(values.size(), CV_8U, cv::Scalar(0));
  for (int r = 0; r < values.rows; ++r)
    for (int c = 0; c < values.cols; ++c)
      if (valid.at<uchar>(r, c))
        gray.at<uchar>(r, c) = static_cast<uchar>(
            std::min(255.0f, std::max(0.0f, values.at<float>(r, c) * factor + 0.5f)));
  EXPECT_EQ(cv::norm(out.gray, gray, cv::NORM_INF), 0);
  EXPECT_DOUBLE_EQ(out.threshold, otsu_of_every_pixel(gray, valid) * out.intensity_scale / 255.0);
  for (int r = 0; r < values.rows; ++r)
    for (int c = 0; c < values.cols; ++c) {
      const int expected = !valid.at<uchar>(r, c)                   ? 0
                           : values.at<float>(r, c) > out.threshold ? 255
                                                                    : 0;
      ASSERT_EQ(out.detect.at<uchar>(r, c), expected) << r << ", " << c;
    }
}

// PreprocessOptions::threads: rows split between threads give the images of one thread, for a
// known and an Otsu threshold, a dense and a sparse image (the second filling pass by blocks or
// not), and a ring image resampled to square pixels (a part starting on a repeated row).
TEST(Preprocess, ThreadsGiveTheOneThreadImages) {
  constexpr double kDeg = M_PI / 180.0;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> level(0, 200);
  std::uniform_int_distribution<int> stretch(1, 200);
  const auto random_image = [&](ProjectedImage& img, double observed_share) {
    const int rows = img.geometry.height, cols = img.geometry.width;
    img.intensity = cv::Mat(rows, cols, CV_32F);
    img.mask = cv::Mat(rows, cols, CV_8U);
    img.range = cv::Mat(rows, cols, CV_32F, cv::Scalar(5));
    std::bernoulli_distribution seen(observed_share);
    for (int r = 0; r < rows; ++r) {
      if (r > 0 && rng() % 10 < 5) {
        img.mask.row(r - 1).copyTo(img.mask.row(r));
      } else {
        for (int c = 0; c < cols;) {
          const bool kind = seen(rng);
          const int end = std::min(cols, c + stretch(rng));
          for (; c < end; ++c) img.mask.at<uchar>(r, c) = kind || seen(rng) ? 255 : 0;
        }
      }
      for (int c = 0; c < cols; ++c)
        img.intensity.at<float>(r, c) = img.mask.at<uchar>(r, c) ? level(rng) : 1e6f;
    }
    img.points_projected = static_cast<std::size_t>(cv::countNonZero(img.mask));
  };
  struct Case {
    const char* name;
    ProjectedImage image;
    std::optional<double> threshold;
  };
  std::vector<Case> cases(4);
  cases[0].name = "dense, known threshold";
  cases[0].image.geometry = geometry_for_bounds({-0.3, 0.3, -0.2, 0.2}, 0.001, 0.001);
  random_image(cases[0].image, 0.8);
  cases[0].threshold = 100;
  cases[1].name = "sparse, Otsu";
  cases[1].image.geometry = cases[0].image.geometry;
  random_image(cases[1].image, 0.3);
  cases[2].name = "dense, Otsu";
  cases[2].image.geometry = cases[0].image.geometry;
  random_image(cases[2].image, 0.9);
  cases[3].name = "ring rows to square pixels";
  cases[3].image.geometry =
      geometry_for_bounds({-3, 3, -16 * kDeg, 16 * kDeg}, 0.1 * kDeg, 0.5 * kDeg);
  for (int r = 0; r < cases[3].image.geometry.height; ++r)
    cases[3].image.geometry.row_elevation.push_back((16 - 0.5 * r) * kDeg);
  cases[3].image.geometry.v0 = 0;
  random_image(cases[3].image, 0.8);
  cases[3].threshold = 100;
  for (const Case& c : cases) {
    ASSERT_GE(c.image.intensity.total(), 3u * 65536u) << c.name << ": too small to split";
    PreprocessOptions opt;
    opt.threshold = c.threshold;
    PreprocessedImage one, split;
    preprocess(c.image, opt, one);
    for (int threads : {2, 3}) {
      opt.threads = threads;
      for (int run = 0; run < 2; ++run) {  // reused buffers too
        preprocess(c.image, opt, split);
        ASSERT_EQ(one.gray.size(), split.gray.size()) << c.name;
        EXPECT_EQ(cv::norm(one.gray, split.gray, cv::NORM_INF), 0) << c.name << threads;
        EXPECT_EQ(cv::norm(one.detect, split.detect, cv::NORM_INF), 0) << c.name << threads;
        EXPECT_EQ(cv::norm(one.valid, split.valid, cv::NORM_INF), 0) << c.name << threads;
        EXPECT_EQ(one.threshold, split.threshold) << c.name << threads;
      }
    }
    // The images hold both levels and filled holes: a comparison that could fail.
    EXPECT_GT(cv::countNonZero(one.detect), 0) << c.name;
    EXPECT_GT(cv::countNonZero(one.valid) - cv::countNonZero(c.image.mask), 0) << c.name;
  }
  EXPECT_GT(cases[3].image.geometry.row_elevation.size(), 1u);
  PreprocessedImage rings;
  preprocess(cases[3].image, PreprocessOptions{}, rings);
  EXPECT_GT(rings.gray.rows, 2 * cases[3].image.intensity.rows) << "no square pixels";
}

}  // namespace
}  // namespace iilfm
