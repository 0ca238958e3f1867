#include "opencv_threads.hpp"

#include <algorithm>
#include <opencv2/core/utility.hpp>

namespace iilfm::cli {

void use_opencv_threads(int threads) { cv::setNumThreads(std::max(1, threads)); }

}  // namespace iilfm::cli
