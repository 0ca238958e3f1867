// The binary image's holes (preprocess.cpp, PreprocessOptions::hole_class_block): each pixel of
// `detect` still unobserved (valid 0) becomes white when most observed pixels around it are white,
// black when most are black, and white when none is observed (the detectors' background: no
// edge). "Around" is the pixel's block of `block` pixels square and the 8 blocks next to it.
#pragma once

#include <opencv2/core.hpp>

#include "iilfm/preprocess.hpp"

namespace iilfm::detail {

constexpr int kMaxHoleClassBlock = 64;  // the 3 x 3 blocks' counts fit 16 bits

// Writes the class of every unobserved pixel of `detect` (CV_8U, 0 or 255) into it; `valid` is
// CV_8U, 0 or 255. One pass over the image: a band of `block` rows is counted, and the band above
// it, whose neighbourhood is then complete, written while its rows are in cache. InputError when
// `block` is outside 1..kMaxHoleClassBlock.
void classify_holes(const cv::Mat& valid, int block, cv::Mat& detect, HoleClassBuffers& buffers);

}  // namespace iilfm::detail
