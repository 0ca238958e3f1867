// Image files without OpenCV's codec module: libopencv_imgcodecs pulls in GDAL, GDCM and about 120
// more libraries, and resolving their symbols took 50-100 ms at every start of a program linking
// it (the `iilfm` program, the Python module, each test process). PNG by libpng, JPEG by
// libjpeg(-turbo), TIFF by libtiff, PGM read directly.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace iilfm {

// PNG bytes of an 8-bit gray (CV_8UC1) or BGR (CV_8UC3) image. `dpi` > 0 adds a pHYs chunk so
// that printing programs size the image. Empty for another layout.
std::vector<std::uint8_t> encode_png(const cv::Mat& image, double dpi = 0);

// JPEG bytes (baseline, `quality` 1-100) of an 8-bit gray or BGR image. Empty for another layout.
std::vector<std::uint8_t> encode_jpeg(const cv::Mat& image, int quality);

// Writes `bytes` to `path`; InputError "<path>: cannot write <what>" when that fails.
void write_bytes_to_file(const std::string& path, const std::vector<std::uint8_t>& bytes,
                         const std::string& what);

// A single-channel 8- or 16-bit image (CV_8UC1 or CV_16UC1, values as stored) from a PNG, PGM
// (P5 or P2) or TIFF file, chosen by the file's first bytes. InputError naming the file when it
// cannot be read, or holds colour, alpha, a palette or another bit depth.
cv::Mat read_intensity_image(const std::string& path);

}  // namespace iilfm
