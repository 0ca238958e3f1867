// Images too small to hold any marker (a degenerate cloud projects to one row or one pixel) give
// no detection from every back-end and never crash. libapriltag 3.3 segfaulted on a 271 x 1 image
// found by the pipeline fuzz target (fuzz/fuzz_pipeline.cpp).
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "iilfm/detector.hpp"

namespace iilfm {
namespace {

TEST(TinyImages, NoDetectionAndNoCrashInEveryBackEnd) {
  cv::RNG rng(7);
  for (const char* family :
       {"apriltag:tag36h11", "apriltag:tag16h5", "aruco:DICT_4X4_50", "rings:ring7h3"}) {
    const auto detector = make_detector(family);
    for (const cv::Size size : {cv::Size(271, 1), cv::Size(1, 271), cv::Size(1, 1), cv::Size(5, 5),
                                cv::Size(40, 2), cv::Size(2, 40), cv::Size(6, 6)}) {
      cv::Mat image(size, CV_8UC1);
      rng.fill(image, cv::RNG::UNIFORM, 0, 256);
      std::vector<Detection> found;
      detector->detect(image, found);
      EXPECT_TRUE(found.empty()) << family << " " << size;
    }
  }
}

}  // namespace
}  // namespace iilfm
