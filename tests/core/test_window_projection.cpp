// The sliding window (FrameWindow) and its incremental projection (WindowProjector) against the
// whole window projected from scratch.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/frame_window.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/window_projection.hpp"
#include "synthetic_frames.hpp"

namespace iilfm {
namespace {

ProjectionOptions mid40_projection() {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid40"), options);
  return options.projection;
}

std::vector<PointCloud> frames(int count) {
  std::vector<PointCloud> out;
  for (int i = 0; i < count; ++i)
    out.push_back(
        testing::livox_like_frame(static_cast<std::uint32_t>(i + 1), 3000 + 700 * (i % 4)));
  return out;
}

TEST(FrameWindow, ViewIsTheLastFramesInOrderAndDroppedIsTheFrameThatLeft) {
  const std::vector<PointCloud> all = frames(11);
  FrameWindow window(4);
  for (std::size_t k = 0; k < all.size(); ++k) {
    window.push(all[k], CloudStats{all[k].size(), all[k].size(), 0, 0});
    const std::size_t first = k >= 3 ? k - 3 : 0;
    std::vector<float> expected_x;
    for (std::size_t f = first; f <= k; ++f)
      expected_x.insert(expected_x.end(), all[f].x.begin(), all[f].x.end());
    const PointView view = window.view();
    ASSERT_EQ(view.size(), expected_x.size()) << "push " << k;
    for (std::size_t i = 0; i < view.size(); ++i) ASSERT_EQ(view.x[i], expected_x[i]);
    EXPECT_EQ(window.newest().size(), all[k].size());
    EXPECT_EQ(window.newest().x[0], all[k].x[0]);
    if (k >= 4) {
      const PointView dropped = window.dropped();
      ASSERT_EQ(dropped.size(), all[k - 4].size());
      EXPECT_EQ(dropped.x[dropped.size() - 1], all[k - 4].x.back());
    } else {
      EXPECT_TRUE(window.dropped().empty());
    }
    EXPECT_EQ(window.stats().valid_points, view.size());
  }
}

TEST(FrameWindow, MovesItsPointsAboutOncePerWindowLength) {
  // Equal frames, as a scanner gives them: the window's first point lies further into the
  // buffer after each push until the buffer is compacted, when it moves back (or the buffer is
  // reallocated). The window must stay readable and be moved rarely, not every few pushes.
  // 60 frames: the buffer, doubled as frames arrive, reached 62 frames, one more than the window
  // and the frame it dropped last.
  const PointCloud frame = testing::livox_like_frame(5, 1000);
  constexpr int kWindow = 60, kPushes = 660;
  FrameWindow window(kWindow);
  const float* last_start = nullptr;
  int moves = 0;
  for (int k = 0; k < kPushes; ++k) {
    window.push(frame, CloudStats{frame.size(), frame.size(), 0, 0});
    const PointView view = window.view();
    ASSERT_EQ(view.size(), frame.size() * static_cast<std::size_t>(std::min(k + 1, kWindow)));
    ASSERT_EQ(view.x[view.size() - 1], frame.x.back());
    const float* start = view.x.data;
    if (k >= kWindow && start <= last_start) ++moves;  // steady state: moved back to the front
    last_start = start;
  }
  // About (kPushes - kWindow) / kWindow = 10 with a buffer twice the window; one just larger
  // than the window moved it on every push.
  EXPECT_GT(moves, 3);
  EXPECT_LT(moves, 20);
}

void expect_same_image(const ProjectedImage& incremental, const ProjectedImage& full,
                       const std::string& where) {
  ASSERT_EQ(incremental.geometry.width, full.geometry.width) << where;
  ASSERT_EQ(incremental.geometry.height, full.geometry.height) << where;
  EXPECT_EQ(incremental.points_projected, full.points_projected) << where;
  int mismatches = 0;
  for (int r = 0; r < full.geometry.height; ++r)
    for (int c = 0; c < full.geometry.width; ++c) {
      const int n = full.count.at<std::int32_t>(r, c);
      bool same = incremental.count.at<std::int32_t>(r, c) == n &&
                  incremental.mask.at<std::uint8_t>(r, c) == full.mask.at<std::uint8_t>(r, c);
      same = same && std::abs(incremental.intensity.at<float>(r, c) -
                              full.intensity.at<float>(r, c)) <= 1e-3f;
      same =
          same && std::abs(incremental.range.at<float>(r, c) - full.range.at<float>(r, c)) <= 1e-5f;
      const int expected_index = n == 1 ? full.index.at<std::int32_t>(r, c) : -1;
      same = same && incremental.index.at<std::int32_t>(r, c) == expected_index;
      mismatches += same ? 0 : 1;
    }
  EXPECT_EQ(mismatches, 0) << where;
}

TEST(WindowProjector, EveryPushMatchesTheWindowProjectedFromScratch) {
  const ProjectionOptions options = mid40_projection();
  ASSERT_TRUE(WindowProjector::supports(options));
  WindowProjector incremental(options);
  SphericalProjector whole(options);
  FrameWindow window(5);
  ProjectedImage inc_image, full_image;
  const std::vector<PointCloud> all = frames(14);
  for (std::size_t k = 0; k < all.size(); ++k) {
    window.push(all[k], {});
    incremental.project(window, inc_image);
    whole.project(window.view(), full_image);
    expect_same_image(inc_image, full_image, "push " + std::to_string(k));
  }
}

TEST(WindowProjector, RebuildsWhenItMissedAPushOrTheImageWasOverwritten) {
  const ProjectionOptions options = mid40_projection();
  WindowProjector incremental(options);
  SphericalProjector whole(options);
  FrameWindow window(3);
  ProjectedImage inc_image, full_image;
  const std::vector<PointCloud> all = frames(8);
  for (std::size_t k = 0; k < 4; ++k) window.push(all[k], {});
  incremental.project(window, inc_image);
  window.push(all[4], {});
  window.push(all[5], {});  // two pushes between calls
  incremental.project(window, inc_image);
  whole.project(window.view(), full_image);
  expect_same_image(inc_image, full_image, "after a missed push");

  whole.project(all[7], inc_image);  // someone else wrote into the image
  window.push(all[6], {});
  incremental.project(window, inc_image);
  whole.project(window.view(), full_image);
  expect_same_image(inc_image, full_image, "after the image was overwritten");
}

TEST(WindowProjector, AnotherWindowIsProjectedFromScratch) {
  const ProjectionOptions options = mid40_projection();
  WindowProjector incremental(options);
  SphericalProjector whole(options);
  FrameWindow first(2), second(2);
  ProjectedImage inc_image, full_image;
  const std::vector<PointCloud> all = frames(6);
  first.push(all[0], {});
  incremental.project(first, inc_image);
  second.push(all[3], {});
  second.push(all[4], {});  // second.pushes() == first.pushes() + 1: only its identity differs
  incremental.project(second, inc_image);
  whole.project(second.view(), full_image);
  expect_same_image(inc_image, full_image, "second window");
}

TEST(WindowProjector, SpinningPresetsAreNotSupported) {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("vlp16"), options);
  EXPECT_FALSE(WindowProjector::supports(options.projection));
  EXPECT_THROW(WindowProjector{options.projection}, InputError);
}

}  // namespace
}  // namespace iilfm
