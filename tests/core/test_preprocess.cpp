#include <gtest/gtest.h>

#include "iilfm/preprocess.hpp"

namespace iilfm {
namespace {

// A 20x20 image: left half intensity 10 (black print), right half 120 (white), one hole in each.
ProjectedImage two_tone() {
  ProjectedImage img;
  img.intensity = cv::Mat(20, 20, CV_32F, cv::Scalar(10));
  img.intensity.colRange(10, 20).setTo(120);
  img.mask = cv::Mat(20, 20, CV_8U, cv::Scalar(255));
  img.range = cv::Mat(20, 20, CV_32F, cv::Scalar(2));
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
  EXPECT_EQ(out.gray.at<uchar>(3, 16), 255);     // 99th percentile maps to 255
}

TEST(Preprocess, UnfilledHolesTakeTheUnobservedValue) {
  PreprocessOptions opt;
  opt.threshold = 60;
  opt.fill_holes = false;
  opt.unobserved_value = 77;
  PreprocessedImage out;
  preprocess(two_tone(), opt, out);
  EXPECT_EQ(out.detect.at<uchar>(12, 15), 77);
  EXPECT_EQ(out.gray.at<uchar>(5, 4), 77);
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

TEST(Preprocess, GrayModeKeepsLevels) {
  PreprocessOptions opt;
  opt.binarize = false;
  PreprocessedImage out;
  preprocess(two_tone(), opt, out);
  EXPECT_NEAR(out.detect.at<uchar>(3, 3), 10 * 255 / 120, 1);
}

}  // namespace
}  // namespace iilfm
