// `iilfm detect IMAGE.png`: the 2-D stages on an intensity image a driver already projected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "cli_run.hpp"
#include "iilfm/apriltag_families.hpp"
#include "real_data.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm {
namespace {

namespace fs = std::filesystem;

using testing::CliRun;
using testing::run_cli;
using testing::slurp;

fs::path temp(const std::string& name) { return iilfm::testing::process_scratch_dir() / name; }

// An Ouster-like image: a tag36h11 printed 6 px per cell on a mid-grey wall, 2:1 aspect cells
// squashed vertically as a 0.35 x 0.7 deg sensor sees them.
TEST(ImageInput, TagInASquashedIntensityImageIsFoundWithPixelCornersOnly) {
  const AprilTagImage tag = render_apriltag("tag36h11", 7);
  cv::Mat print(tag.total_width, tag.total_width, CV_8U);
  for (int r = 0; r < tag.total_width; ++r)
    for (int c = 0; c < tag.total_width; ++c)
      print.at<std::uint8_t>(r, c) = tag.pixels[static_cast<std::size_t>(r * tag.total_width + c)];
  cv::Mat big;
  cv::resize(print, big, cv::Size(tag.total_width * 6, tag.total_width * 3), 0, 0,
             cv::INTER_NEAREST);
  cv::Mat image(64, 300, CV_8U, cv::Scalar(90));
  big.convertTo(big, CV_8U, 200.0 / 255.0, 20);  // black 20, white 220
  big.copyTo(image(cv::Rect(120, 16, big.cols, big.rows)));
  image.rowRange(0, 4).setTo(0);  // no returns (sky)
  const fs::path png = temp("squashed.png"), json = temp("squashed.json");
  ASSERT_TRUE(cv::imwrite(png.string(), image));

  const CliRun r =
      run_cli("detect " + png.string() + " --res-h 0.35 --res-v 0.7 --json " + json.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("2-D stages only"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["markers"].size(), 1u);
  const auto& m = j["markers"][0];
  EXPECT_EQ(m["id"], 7);
  // The black square's outer corners: one cell (6 x 3 px) inside the print's white margin.
  const int margin = (tag.total_width - tag.width_at_border) / 2;
  const double left = 120 + 6 * margin - 0.5, top = 16 + 3 * margin - 0.5;
  const double right = left + 6 * tag.width_at_border, bottom = top + 3 * tag.width_at_border;
  const double expected[4][2] = {{left, top}, {right, top}, {right, bottom}, {left, bottom}};
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(m["corners_px"][k][0].get<double>(), expected[k][0], 0.6) << k;
    EXPECT_NEAR(m["corners_px"][k][1].get<double>(), expected[k][1], 0.6) << k;
  }
  EXPECT_TRUE(m["corners_lidar"].empty());
  EXPECT_TRUE(j["pose"].is_null());
  EXPECT_EQ(j["pose_missing_reason"], "2-D image input: no 3-D points");
  EXPECT_EQ(j["input"]["kind"], "image");

  // --ids holds for an image too: id 7 not among them, nothing reported, and said so.
  const CliRun other = run_cli("detect " + png.string() +
                               " --res-h 0.35 --res-v 0.7 --ids 0-6,8 --json " + json.string());
  ASSERT_EQ(other.status, 0) << other.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(json))["markers"].size(), 0u);
  EXPECT_NE(other.out.find("0 marker(s) (and 1 of ids not given with --ids, not reported)"),
            std::string::npos)
      << other.out;
}

TEST(ImageInput, NotAnImageIsAOneLineError) {
  const fs::path fake = temp("fake.png");
  std::ofstream(fake) << "not a png";
  const CliRun r = run_cli("detect " + fake.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(fake.string() + ": cannot read the image"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  EXPECT_TRUE(r.out.empty());
}

// A recording's outputs would be silently missing for an image: refused, nothing written.
TEST(ImageInput, RecordingOptionsAreRefusedForAnImage) {
  const fs::path png = temp("plain.png");
  ASSERT_TRUE(cv::imwrite(png.string(), cv::Mat(32, 64, CV_8U, cv::Scalar(90))));
  const fs::path jsonl = temp("plain.jsonl");
  for (const std::string option :
       {"--jsonl " + jsonl.string(), std::string("--tum -"), std::string("--topic /points")}) {
    const CliRun r = run_cli("detect " + png.string() + " " + option);
    EXPECT_EQ(r.status, 2) << option;
    EXPECT_EQ(r.err, "iilfm: " + png.string() +
                         ": --jsonl, --tum and --topic take a recording; an image gives --json "
                         "and --image\n")
        << option;
    EXPECT_TRUE(r.out.empty()) << option;
  }
  EXPECT_FALSE(fs::exists(jsonl));
}

// SOURCES.md: the real OS1-64 image holds tag36h11 ids 0 and 3 that its source project decodes,
// and a third, coarser sheet. The local threshold, the default for an image, finds all three and
// nothing else; Otsu's global threshold over the whole room (176 of 255) keeps only id 0.
TEST(ImageInput, RealOusterImageWithTheLocalThresholdByDefault) {
  const fs::path png =
      testing::real_data_dir() / "srrg2_ouster_intensity" / "ouster_intensity_0.png";
  if (!fs::exists(png)) GTEST_SKIP() << "no real data at " << png;
  const fs::path json = temp("ouster.json");
  const auto ids_found = [&](const std::string& options) {
    const CliRun r =
        run_cli("detect " + png.string() + " " + options + " -q --json " + json.string());
    EXPECT_EQ(r.status, 0) << r.err;
    std::set<int> ids;
    const nlohmann::json result = nlohmann::json::parse(slurp(json));
    for (const auto& m : result["markers"]) ids.insert(m["id"].get<int>());
    return ids;
  };
  for (const std::string options : {"", "--sensor os1-64", "--threshold local"})
    EXPECT_EQ(ids_found(options), (std::set<int>{0, 1, 3})) << options;
  EXPECT_EQ(ids_found("--threshold otsu"), (std::set<int>{0}));
}

}  // namespace
}  // namespace iilfm
