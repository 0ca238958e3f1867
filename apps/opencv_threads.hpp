// The threads OpenCV's own parallel loops may use in this program: as many as --threads says
// (one by default), like the pipeline's own parts.
#pragma once

namespace iilfm::cli {

// OpenCV's parallel loops (cv::threshold inside cv::findContours, ArUco's adaptive thresholds)
// otherwise wake its thread pool for images of a few hundred thousand pixels, whose workers then
// spin on the other core: a VLP-16 recording took 1.73 s of CPU and 1.30 s instead of 1.44 s and
// 1.19 s (docs/performance.md, session 18). A process-wide setting: the program's to make, not
// the library's.
void use_opencv_threads(int threads);

}  // namespace iilfm::cli
