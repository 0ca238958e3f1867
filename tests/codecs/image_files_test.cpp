// include/iilfm/image_files.hpp against OpenCV's codecs: what iilfm writes, OpenCV reads back the
// same; what OpenCV writes (PNG, PGM, TIFF at 8 and 16 bits), iilfm reads back the same; and the
// files iilfm refuses, with one line naming the file.
#include "iilfm/image_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_run.hpp"
#include "iilfm/error.hpp"

namespace iilfm {
namespace {

namespace fs = std::filesystem;

cv::Mat pattern(int type) {
  cv::Mat image(37, 53, type);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256));
  return image;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

void write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_error(const std::string& path) {
  try {
    read_intensity_image(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ImageFiles, PngAndJpegWrittenAreWhatOpenCvReads) {
  for (const int type : {CV_8UC1, CV_8UC3}) {
    const cv::Mat image = pattern(type);
    const std::vector<std::uint8_t> png = encode_png(image);
    ASSERT_FALSE(png.empty());
    EXPECT_TRUE(same(cv::imdecode(png, cv::IMREAD_UNCHANGED), image)) << type;

    // JPEG is lossy: a smooth picture comes back close (PSNR), in the same channel order.
    cv::Mat smooth;
    cv::GaussianBlur(image, smooth, {0, 0}, 4);
    const std::vector<std::uint8_t> jpeg = encode_jpeg(smooth, 90);
    ASSERT_FALSE(jpeg.empty());
    const cv::Mat decoded = cv::imdecode(jpeg, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(decoded.type(), smooth.type());
    EXPECT_GT(cv::PSNR(decoded, smooth), 35.0) << type;
  }
  // Other layouts are not encoded.
  EXPECT_TRUE(encode_png(cv::Mat(4, 4, CV_32F, 1.0f)).empty());
  EXPECT_TRUE(encode_jpeg(cv::Mat(4, 4, CV_8UC4), 90).empty());
}

TEST(ImageFiles, PngCarriesItsDotsPerInch) {
  const std::vector<std::uint8_t> png = encode_png(pattern(CV_8UC1), 300);
  const std::string bytes(png.begin(), png.end());
  const std::size_t at = bytes.find("pHYs");
  ASSERT_NE(at, std::string::npos);
  // 300 dpi = 11811 pixels per metre, both axes, unit 1 (metre).
  const auto u32 = [&](std::size_t i) {
    return static_cast<std::uint32_t>(png[i]) << 24 | png[i + 1] << 16 | png[i + 2] << 8 |
           png[i + 3];
  };
  EXPECT_EQ(u32(at + 4), 11811u);
  EXPECT_EQ(u32(at + 8), 11811u);
  EXPECT_EQ(png[at + 12], 1);
  EXPECT_EQ(encode_png(pattern(CV_8UC1)).size() + 21, png.size());  // the chunk only
}

TEST(ImageFiles, IntensityImagesOpenCvWritesReadBackExactly) {
  const fs::path d = testing::cli_temp_dir() / "image_files";
  fs::create_directories(d);
  for (const int type : {CV_8UC1, CV_16UC1}) {
    const cv::Mat image = pattern(type);
    for (const char* extension : {".png", ".pgm", ".tif"}) {
      const fs::path path = d / (std::to_string(type) + extension);
      ASSERT_TRUE(cv::imwrite(path.string(), image));
      EXPECT_TRUE(same(read_intensity_image(path.string()), image)) << path;
    }
  }
  // A plain (ASCII) PGM with comments, and a 1-bit gray PNG widened to 0/255.
  write(d / "ascii.pgm", "P2\n# made by hand\n3 2\n# max\n1000\n0 1 2\n998 999 1000\n");
  const cv::Mat ascii = read_intensity_image((d / "ascii.pgm").string());
  ASSERT_EQ(ascii.type(), CV_16UC1);
  EXPECT_EQ(ascii.at<std::uint16_t>(1, 2), 1000);
  cv::Mat bits = pattern(CV_8UC1) > 127;
  ASSERT_TRUE(cv::imwrite((d / "bits.png").string(), bits, {cv::IMWRITE_PNG_BILEVEL, 1}));
  EXPECT_TRUE(same(read_intensity_image((d / "bits.png").string()), bits));
}

TEST(ImageFiles, OtherImagesAreRefusedWithOneLineNamingTheFile) {
  const fs::path d = testing::cli_temp_dir() / "image_files_bad";
  fs::create_directories(d);
  const auto expect_refused = [&](const fs::path& path, const std::string& problem) {
    const std::string error = read_error(path.string());
    EXPECT_EQ(error.rfind(path.string() + ": cannot read the image: ", 0), 0u) << error;
    EXPECT_NE(error.find(problem), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  };
  ASSERT_TRUE(cv::imwrite((d / "colour.png").string(), pattern(CV_8UC3)));
  expect_refused(d / "colour.png", "a colour image");
  ASSERT_TRUE(cv::imwrite((d / "alpha.png").string(), pattern(CV_8UC4)));
  expect_refused(d / "alpha.png", "colour");
  ASSERT_TRUE(cv::imwrite((d / "float.tif").string(), cv::Mat(5, 5, CV_32F, 1.5f)));
  expect_refused(d / "float.tif", "32-bit");
  ASSERT_TRUE(cv::imwrite((d / "colour.tif").string(), pattern(CV_8UC3)));
  expect_refused(d / "colour.tif", "3 samples per pixel");

  std::vector<std::uint8_t> png = encode_png(pattern(CV_8UC1));
  write(d / "cut.png", std::string(png.begin(), png.begin() + png.size() / 2));
  expect_refused(d / "cut.png", "");
  write(d / "cut.pgm", "P5 10 10 255\nabc");
  expect_refused(d / "cut.pgm", "PGM data ends early");
  write(d / "text.png", "# .PCD v0.7\n");
  expect_refused(d / "text.png", "not a PNG, PGM or TIFF file");
  EXPECT_NE(read_error((d / "missing.png").string()).find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace iilfm
