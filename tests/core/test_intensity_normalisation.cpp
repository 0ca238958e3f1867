// Intensity normalisation (include/iilfm/intensity_normalisation.hpp) on range images of planes
// whose incidence and range are known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "iilfm/intensity_normalisation.hpp"
#include "iilfm/preprocess.hpp"
#include "iilfm/projection.hpp"

namespace iilfm {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A plane n . p = distance seen through a uniform 0.2 deg image, every pixel observed (except a
// dropout pattern), its intensity the raw return of a surface of `reflectivity`:
// reflectivity * cos(incidence) * (10 m / range)^2, plus Gaussian range noise.
struct PlaneScan {
  ProjectedImage image;
  cv::Mat cos_incidence;  // the truth
};

PlaneScan plane_scan(const Vec3& normal, double distance, double reflectivity,
                     double range_sigma = 0, int width = 151, int height = 101) {
  PlaneScan s;
  ImageGeometry& g = s.image.geometry;
  g.width = width;
  g.height = height;
  g.res_h = g.res_v = 0.2 * kDeg * 151 / width;
  g.u0 = (width - 1) / 2.0;
  g.v0 = (height - 1) / 2.0;
  s.image.intensity = cv::Mat::zeros(g.height, g.width, CV_32F);
  s.image.range = cv::Mat::zeros(g.height, g.width, CV_32F);
  s.image.mask = cv::Mat::zeros(g.height, g.width, CV_8U);
  s.cos_incidence = cv::Mat::ones(g.height, g.width, CV_32F);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, range_sigma > 0 ? range_sigma : 1);
  const Vec3 n = normal.normalized();
  for (int r = 0; r < g.height; ++r)
    for (int c = 0; c < g.width; ++c) {
      if ((r * 7 + c * 3) % 11 == 0) continue;  // dropouts
      const Vec3 d = g.ray(c, r);
      const double range = distance / std::abs(n.dot(d));
      const double cos_i = std::abs(n.dot(d));
      s.image.range.at<float>(r, c) =
          static_cast<float>(range + (range_sigma > 0 ? range_sigma * noise(rng) : 0));
      s.image.intensity.at<float>(r, c) =
          static_cast<float>(reflectivity * cos_i * std::pow(10.0 / range, 2));
      s.image.mask.at<std::uint8_t>(r, c) = 255;
      s.cos_incidence.at<float>(r, c) = static_cast<float>(cos_i);
    }
  return s;
}

// Mean and largest relative error of `values` against `truth` over observed pixels at least
// `margin` pixels inside the image.
std::pair<double, double> relative_error(const cv::Mat& values, const cv::Mat& truth,
                                         const cv::Mat& mask, int margin) {
  double sum = 0, worst = 0;
  int n = 0;
  for (int r = margin; r < values.rows - margin; ++r)
    for (int c = margin; c < values.cols - margin; ++c) {
      if (!mask.at<std::uint8_t>(r, c)) continue;
      const double e = std::abs(values.at<float>(r, c) / truth.at<float>(r, c) - 1);
      sum += e;
      worst = std::max(worst, e);
      ++n;
    }
  return {sum / n, worst};
}

TEST(IntensityNormalisation, IncidenceFromTheRangeImageMatchesTheTruthOnTiltedPlanes) {
  NormalisationOptions options;
  options.mode = IntensityNormalisation::kRangeIncidence;
  NormalisationBuffers work;
  // Facing the LiDAR, turned 40 deg about z, tilted 55 deg about y (cos down to about 0.5).
  for (const Vec3& normal : {Vec3(1, 0, 0), Vec3(std::cos(40 * kDeg), std::sin(40 * kDeg), 0),
                             Vec3(std::cos(55 * kDeg), 0, std::sin(55 * kDeg))}) {
    const PlaneScan s = plane_scan(normal, 6, 100);
    cv::Mat cos_estimate;
    estimate_cos_incidence(s.image, options, work, cos_estimate);
    const auto [mean, worst] = relative_error(cos_estimate, s.cos_incidence, s.image.mask, 0);
    EXPECT_LT(mean, 0.01) << normal.transpose();
    EXPECT_LT(worst, 0.08) << normal.transpose();  // the worst at the image border
  }
}

TEST(IntensityNormalisation, RangeIncidenceRecoversTheReflectivityDespiteRangeNoise) {
  // 3 cm range noise, as a spinning LiDAR's: the 1 deg windows average it out.
  const PlaneScan s = plane_scan(Vec3(std::cos(50 * kDeg), std::sin(50 * kDeg), 0), 4, 80, 0.03);
  NormalisationOptions options;
  NormalisationBuffers work;
  cv::Mat out;
  options.mode = IntensityNormalisation::kRangeIncidence;
  normalise_intensity(s.image, options, work, out);
  const cv::Mat reflectivity(out.size(), CV_32F, cv::Scalar(80));
  const auto [mean, worst] = relative_error(out, reflectivity, s.image.mask, 5);
  EXPECT_LT(mean, 0.05);
  EXPECT_LT(worst, 0.25);
  // Range alone leaves the cosine in (about 0.55-0.75 here).
  options.mode = IntensityNormalisation::kRange;
  normalise_intensity(s.image, options, work, out);
  const auto [range_only_mean, range_only_worst] =
      relative_error(out, reflectivity, s.image.mask, 5);
  EXPECT_GT(range_only_mean, 0.2);
  (void)range_only_worst;
  // Unobserved pixels stay 0.
  for (int r = 0; r < out.rows; ++r)
    for (int c = 0; c < out.cols; ++c)
      if (!s.image.mask.at<std::uint8_t>(r, c)) {
        ASSERT_EQ(out.at<float>(r, c), 0.0f);
      }
}

TEST(IntensityNormalisation, AWallMeetingTheFloorIsNotCorrectedAsIfItWereTilted) {
  // An OS1-128 (0.176 deg columns at 2048, 0.354 deg rings) 0.85 m above a floor that meets a
  // wall 18 m away, 3 cm range noise. Windows reaching across the crease see the floor's ranges
  // below the wall's: a two-sided slope there made the wall's lowest rows look tilted by 75-80 deg
  // and 4-5 times brighter, enough to move Otsu's threshold off the markers on that wall.
  ProjectedImage image;
  ImageGeometry& g = image.geometry;
  g.width = 101;
  g.height = 61;
  g.res_h = 0.176 * kDeg;
  g.res_v = 0.354 * kDeg;
  g.u0 = 50;
  g.v0 = 30 - std::atan2(0.85, 18.0) / g.res_v;  // the crease on the middle row
  image.intensity = cv::Mat::zeros(g.height, g.width, CV_32F);
  image.range = cv::Mat::zeros(g.height, g.width, CV_32F);
  image.mask = cv::Mat(g.height, g.width, CV_8U, cv::Scalar(255));
  cv::Mat on_wall(g.height, g.width, CV_8U, cv::Scalar(0));
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.03);
  for (int r = 0; r < g.height; ++r)
    for (int c = 0; c < g.width; ++c) {
      const Vec3 d = g.ray(c, r);
      const double to_wall = 18.0 / d.x();
      const double to_floor = d.z() < 0 ? -0.85 / d.z() : to_wall + 1;
      image.range.at<float>(r, c) = static_cast<float>(std::min(to_wall, to_floor) + noise(rng));
      image.intensity.at<float>(r, c) = 20;
      on_wall.at<std::uint8_t>(r, c) = to_wall < to_floor;
    }
  NormalisationOptions options;
  options.mode = IntensityNormalisation::kRangeIncidence;
  NormalisationBuffers work;
  cv::Mat cos_estimate;
  estimate_cos_incidence(image, options, work, cos_estimate);
  double lowest_on_wall = 1;
  int wall_pixels = 0;
  for (int r = 0; r < g.height; ++r)
    for (int c = 0; c < g.width; ++c)
      if (on_wall.at<std::uint8_t>(r, c)) {
        lowest_on_wall = std::min(lowest_on_wall, double{cos_estimate.at<float>(r, c)});
        ++wall_pixels;
      }
  ASSERT_GT(wall_pixels, 1000);
  // The wall faces the LiDAR within 2.7 deg (cos above 0.998). Measured: 0.89 at worst (the
  // windows' noise and what of the floor the pixel's own window holds), 0.25 before.
  EXPECT_GT(lowest_on_wall, 0.85);
}

TEST(IntensityNormalisation, ThreadsGiveTheOneThreadImages) {
  // 601 x 401 pixels of 0.05 deg (three parts of at least 64k), 1 cm range noise; the windows
  // summed directly (0.25 deg: 5 pixels each way) and by cv::boxFilter (1 deg: 20, over 8).
  const PlaneScan s =
      plane_scan(Vec3(std::cos(30 * kDeg), std::sin(30 * kDeg), 0.3), 5, 80, 0.01, 601, 401);
  for (const double half_window_deg : {0.25, 1.0}) {
    for (const IntensityNormalisation mode :
         {IntensityNormalisation::kRange, IntensityNormalisation::kRangeIncidence}) {
      NormalisationOptions options;
      options.mode = mode;
      options.normal_half_window_deg = half_window_deg;
      NormalisationBuffers one_work, split_work;
      cv::Mat one, split;
      normalise_intensity(s.image, options, one_work, one);
      for (int threads : {2, 3}) {
        for (int run = 0; run < 2; ++run) {
          normalise_intensity(s.image, options, split_work, split, threads);
          EXPECT_EQ(cv::norm(one, split, cv::NORM_INF), 0) << half_window_deg << threads;
          if (mode == IntensityNormalisation::kRangeIncidence) {
            EXPECT_EQ(cv::norm(one_work.cos_incidence, split_work.cos_incidence, cv::NORM_INF), 0)
                << half_window_deg << threads;
          }
        }
      }
      if (mode == IntensityNormalisation::kRangeIncidence) {  // the cosines vary: a real check
        double lo = 0, hi = 0;
        cv::minMaxLoc(one_work.cos_incidence, &lo, &hi, nullptr, nullptr, s.image.mask);
        EXPECT_LT(lo, hi - 0.05) << half_window_deg;
      }
    }
  }
}

// The windows' observed-pixel counts and centroids (the sums slid down the rows) against naive
// sums: exact, for windows summed directly (up to 8 pixels each way) and by cv::boxFilter, in one
// part and in three (a part's first row summed whole).
TEST(IntensityNormalisation, WindowCountsAndCentroidsAreExact) {
  const PlaneScan s =
      plane_scan(Vec3(std::cos(20 * kDeg), std::sin(20 * kDeg), 0.2), 6, 80, 0.01, 601, 401);
  cv::Mat mask = s.image.mask.clone();
  mask(cv::Rect(100, 50, 120, 90)).setTo(0);  // a hole wider than a window
  ProjectedImage image = s.image;
  image.mask = mask;
  const ImageGeometry& g = image.geometry;
  const int rows = g.height, cols = g.width;
  for (const double half_window_deg : {0.05, 0.39, 0.5}) {  // 1, 8 and 10 pixels each way
    NormalisationOptions options;
    options.mode = IntensityNormalisation::kRangeIncidence;
    options.normal_half_window_deg = half_window_deg;
    const int a = static_cast<int>(std::lround(half_window_deg * kDeg / g.res_h));
    const int b = static_cast<int>(std::lround(half_window_deg * kDeg / g.res_v));
    for (const int threads : {1, 3}) {
      NormalisationBuffers work;
      cv::Mat cosines;
      estimate_cos_incidence(image, options, work, cosines, threads);
      int wrong = 0;
      for (int r = 0; r < rows; r += 3) {
        for (int c = 0; c < cols; c += 2) {
          double count = 0, col = 0, row = 0;
          for (int rr = std::max(0, r - b); rr <= std::min(rows - 1, r + b); ++rr)
            for (int cc = std::max(0, c - a); cc <= std::min(cols - 1, c + a); ++cc)
              if (mask.at<std::uint8_t>(rr, cc)) {
                ++count;
                col += cc;
                row += rr;
              }
          const float n = work.weight_sum.at<float>(r, c);
          wrong += n != static_cast<float>(count);
          if (count == 0) continue;
          wrong +=
              work.col_sum.at<float>(r, c) != static_cast<float>(col) / static_cast<float>(count);
          wrong +=
              work.row_sum.at<float>(r, c) != static_cast<float>(row) / static_cast<float>(count);
        }
      }
      EXPECT_EQ(wrong, 0) << half_window_deg << " deg, " << threads << " threads";
    }
  }
}

TEST(IntensityNormalisation, RangeNormalisationIsTheSquareLawAboutTheReference) {
  const PlaneScan near = plane_scan(Vec3(1, 0, 0), 2, 100);
  const PlaneScan far = plane_scan(Vec3(1, 0, 0), 12, 100);
  NormalisationOptions options;
  options.mode = IntensityNormalisation::kRange;
  NormalisationBuffers work;
  cv::Mat a, b;
  normalise_intensity(near.image, options, work, a);
  normalise_intensity(far.image, options, work, b);
  // Raw: 36x apart at the centre pixel; normalised: the same, reflectivity x cos.
  EXPECT_NEAR(near.image.intensity.at<float>(50, 75) / far.image.intensity.at<float>(50, 75), 36,
              0.01);
  EXPECT_NEAR(a.at<float>(50, 75), 100, 0.01);
  EXPECT_NEAR(b.at<float>(50, 75), 100, 0.01);
}

TEST(IntensityNormalisation, OffLeavesPreprocessingAsItWasAndOnAltersNoProjectedImage) {
  const PlaneScan s = plane_scan(Vec3(1, 0.3, 0), 5, 100);
  PreprocessOptions options;
  options.threshold = 50;
  PreprocessedImage plain, normalised;
  preprocess(s.image, options, plain);
  EXPECT_TRUE(plain.normalised.empty());  // off: no pass at all
  const cv::Mat intensity = s.image.intensity.clone(), range = s.image.range.clone();
  options.normalise.mode = IntensityNormalisation::kRangeIncidence;
  preprocess(s.image, options, normalised);
  EXPECT_EQ(cv::norm(intensity, s.image.intensity, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(range, s.image.range, cv::NORM_INF), 0);
  // Raw intensity at 5 m is 4x the reflectivity, so all white; normalised it is 100 > 50 too, and
  // the display scale (twice the 99th percentile) follows the normalised values.
  EXPECT_NEAR(normalised.intensity_scale, 200, 10);
  EXPECT_GT(plain.intensity_scale, 600);
}

}  // namespace
}  // namespace iilfm
