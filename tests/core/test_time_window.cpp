// The time window (`--window-seconds`, FrameWindow::over_seconds): which frames it keeps, when it
// is full, and that its incremental projection still matches the window projected from scratch
// when one push drops several frames.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/frame_window.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/window_projection.hpp"
#include "synthetic_frames.hpp"

namespace iilfm {
namespace {

PointCloud frame(int i) {
  return testing::livox_like_frame(static_cast<std::uint32_t>(i + 1), 2000 + 300 * (i % 3));
}

TEST(TimeWindow, KeepsTheFramesOfTheLastSecondsAndIsFullOnceTheySpanThem) {
  FrameWindow window = FrameWindow::over_seconds(1.0);
  FrameWindow by_count(10);
  for (int i = 0; i < 25; ++i) {
    const PointCloud f = frame(i);
    const double stamp = 100.0 + 0.1 * i;  // 10 Hz, stamps as a driver writes them
    window.push(f, {}, stamp);
    by_count.push(f, {});
    // Frames less than 1 s older than the newest: 10 of them at 10 Hz, as --frames 10.
    EXPECT_EQ(window.size(), std::min(i + 1, 10)) << "push " << i;
    EXPECT_EQ(window.full(), i >= 9) << "push " << i;
    EXPECT_EQ(window.full(), by_count.full()) << "push " << i;
    ASSERT_EQ(window.view().size(), by_count.view().size()) << "push " << i;
  }
}

TEST(TimeWindow, OnePushMayDropSeveralFramesOrNone) {
  FrameWindow window = FrameWindow::over_seconds(0.5);
  std::vector<PointCloud> frames;
  for (int i = 0; i < 6; ++i) frames.push_back(frame(i));
  const double stamps[] = {0.0, 0.1, 0.2, 0.3, 0.9, 0.95};
  for (int i = 0; i < 4; ++i) window.push(frames[i], {}, stamps[i]);
  EXPECT_EQ(window.size(), 4u);
  EXPECT_FALSE(window.full());            // 0.3 s + one 0.1 s interval < 0.5 s
  window.push(frames[4], {}, stamps[4]);  // 0.9: frames at 0.4 or before leave, all four
  EXPECT_EQ(window.size(), 1u);
  EXPECT_TRUE(window.full());
  EXPECT_EQ(window.dropped().size(),
            frames[0].size() + frames[1].size() + frames[2].size() + frames[3].size());
  EXPECT_EQ(window.dropped().x[0], frames[0].x[0]);
  window.push(frames[5], {}, stamps[5]);  // 0.95: nothing is 0.5 s old
  EXPECT_EQ(window.size(), 2u);
  EXPECT_TRUE(window.dropped().empty());
  EXPECT_TRUE(window.full());  // stays full
}

TEST(TimeWindow, RefusesBadSecondsAndStamps) {
  EXPECT_THROW(FrameWindow::over_seconds(0), InputError);
  EXPECT_THROW(FrameWindow::over_seconds(-1), InputError);
  EXPECT_THROW(FrameWindow::over_seconds(NAN), InputError);
  FrameWindow window = FrameWindow::over_seconds(1);
  EXPECT_THROW(window.push(frame(0), {}, NAN), InputError);
  FrameWindow by_count(3);
  EXPECT_NO_THROW(by_count.push(frame(0), {}, NAN));  // a count window ignores stamps
}

TEST(TimeWindow, IncrementalProjectionMatchesTheWholeWindowWhenSeveralFramesLeave) {
  PipelineOptions preset;
  apply_sensor_preset(find_sensor_preset("mid40"), preset);
  const ProjectionOptions options = preset.projection;
  ASSERT_TRUE(WindowProjector::supports(options));
  WindowProjector incremental(options);
  SphericalProjector whole(options);
  FrameWindow window = FrameWindow::over_seconds(0.35);
  ProjectedImage inc_image, full_image;
  // Irregular stamps: some pushes drop none, some one, some three frames.
  const double stamps[] = {0, 0.1, 0.2, 0.3, 0.4, 0.45, 0.5, 0.9, 1.0, 1.05, 1.1, 1.6, 1.7};
  for (int k = 0; k < 13; ++k) {
    window.push(frame(k), {}, stamps[k]);
    incremental.project(window, inc_image);
    whole.project(window.view(), full_image);
    ASSERT_EQ(inc_image.points_projected, full_image.points_projected) << "push " << k;
    cv::Mat differs;
    cv::compare(inc_image.count, full_image.count, differs, cv::CMP_NE);
    EXPECT_EQ(cv::countNonZero(differs), 0) << "push " << k;
    cv::compare(inc_image.mask, full_image.mask, differs, cv::CMP_NE);
    EXPECT_EQ(cv::countNonZero(differs), 0) << "push " << k;
    double max_range_diff = 0;
    cv::minMaxLoc(cv::abs(inc_image.range - full_image.range), nullptr, &max_range_diff);
    EXPECT_LT(max_range_diff, 1e-3) << "push " << k;
  }
}

}  // namespace
}  // namespace iilfm
