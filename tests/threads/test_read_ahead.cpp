// Reading a recording ahead on its own thread (io::read_ahead) delivers what the source delivers,
// in its order, errors included, and never leaves its thread running. Run under ThreadSanitizer
// by scripts/tsan.sh (CI).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/io/frame_source.hpp"
#include "iilfm/io/read_ahead.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm::io {
namespace {

// Frames 0, 1, ... with `k + 1` points each (point j at x = k, y = j), then the end or, after
// `fail_after` frames, the InputError a damaged recording raises.
class CountingSource : public FrameSource {
 public:
  CountingSource(std::size_t frames, std::size_t fail_after, std::atomic<std::size_t>* reads)
      : frames_(frames), fail_after_(fail_after), reads_(reads) {}
  bool next(Frame& frame) override {
    const std::size_t k = (*reads_)++;
    if (k == fail_after_) throw file_error(name_, "chunk " + std::to_string(k) + " is damaged");
    if (k >= frames_) return false;
    frame.index = k;
    frame.stamp_s = 0.1 * static_cast<double>(k);
    frame.source = name_ + "#" + std::to_string(k);
    PointCloud& cloud = frame.loaded.cloud;
    cloud = PointCloud();
    for (std::size_t j = 0; j <= k; ++j)
      cloud.push_back(static_cast<float>(k), static_cast<float>(j), 1.0f, 50.0f);
    frame.loaded.stats.valid_points = cloud.size();
    return true;
  }
  std::size_t total() const override { return frames_; }
  const std::string& name() const override { return name_; }

 private:
  std::size_t frames_, fail_after_;
  std::atomic<std::size_t>* reads_;
  std::string name_ = "rec.bag";
};

void expect_frame(const Frame& frame, std::size_t k) {
  EXPECT_EQ(frame.index, k);
  EXPECT_DOUBLE_EQ(frame.stamp_s, 0.1 * static_cast<double>(k));
  EXPECT_EQ(frame.source, "rec.bag#" + std::to_string(k));
  ASSERT_EQ(frame.loaded.cloud.size(), k + 1);
  for (std::size_t j = 0; j <= k; ++j) {
    EXPECT_EQ(frame.loaded.cloud.x[j], static_cast<float>(k));
    EXPECT_EQ(frame.loaded.cloud.y[j], static_cast<float>(j));
  }
}

TEST(ReadAhead, DeliversEveryFrameInOrderThenTheEndAtAnyDepth) {
  for (const std::size_t depth : {1, 2, 5}) {
    std::atomic<std::size_t> reads{0};
    const auto source = read_ahead(std::make_unique<CountingSource>(40, 1000, &reads), depth);
    EXPECT_EQ(source->total(), 40u);
    EXPECT_EQ(source->name(), "rec.bag");
    Frame frame;
    for (std::size_t k = 0; k < 40; ++k) {
      ASSERT_TRUE(source->next(frame)) << "depth " << depth << ", frame " << k;
      expect_frame(frame, k);
    }
    EXPECT_FALSE(source->next(frame));
    EXPECT_FALSE(source->next(frame));  // and stays at the end
  }
}

TEST(ReadAhead, AnErrorComesAfterTheFramesReadBeforeIt) {
  std::atomic<std::size_t> reads{0};
  const auto source = read_ahead(std::make_unique<CountingSource>(40, 7, &reads), 3);
  Frame frame;
  for (std::size_t k = 0; k < 7; ++k) {
    ASSERT_TRUE(source->next(frame));
    expect_frame(frame, k);
  }
  try {
    source->next(frame);
    FAIL() << "no error after frame 6";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rec.bag: chunk 7 is damaged");
  }
  EXPECT_THROW(source->next(frame), InputError);  // a broken source stays broken
  EXPECT_EQ(reads.load(), 8u);                    // nothing read past the damage
}

// The queue is bounded: a caller that stops early finds at most `depth` frames read ahead (plus
// the one the reader was taking when the queue filled), and destroying the source stops the
// reader instead of leaving it blocked on the full queue.
TEST(ReadAhead, ReadsAtMostItsDepthAheadAndStopsWhenDestroyed) {
  std::atomic<std::size_t> reads{0};
  {
    const auto source = read_ahead(std::make_unique<CountingSource>(1000, 1000, &reads), 2);
    Frame frame;
    ASSERT_TRUE(source->next(frame));
    expect_frame(frame, 0);
    // Time for an unbounded reader to run far ahead; a bounded one waits on the full queue.
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_LE(reads.load(), 1u + 2u + 1u);
  }  // joins the reader: a hang here is the failure
  EXPECT_GE(reads.load(), 1u);
  EXPECT_LE(reads.load(), 1u + 2u + 1u);
}

// A folder of PCD files read ahead gives the frames the plain folder source gives.
TEST(ReadAhead, AFolderGivesWhatItsPlainSourceGives) {
  const std::filesystem::path dir = iilfm::testing::process_scratch_dir() / "read_ahead";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (int k = 0; k < 6; ++k) {
    PointCloud cloud;
    for (int j = 0; j < 100 * (k + 1); ++j)
      cloud.push_back(1.0f + 0.01f * static_cast<float>(j), static_cast<float>(k), 0.5f,
                      static_cast<float>(j % 200));
    write_pcd((dir / (std::to_string(1700000000 + k) + ".pcd")).string(), cloud);
  }
  const auto plain = open_frame_source(dir.string(), "");
  const auto ahead = read_ahead(open_frame_source(dir.string(), ""));
  EXPECT_EQ(ahead->total(), plain->total());
  Frame a, b;
  std::size_t frames = 0;
  while (plain->next(a)) {
    ASSERT_TRUE(ahead->next(b)) << frames;
    EXPECT_EQ(b.index, a.index);
    EXPECT_EQ(b.stamp_s, a.stamp_s);
    EXPECT_EQ(b.source, a.source);
    EXPECT_EQ(b.loaded.cloud.x, a.loaded.cloud.x);
    EXPECT_EQ(b.loaded.cloud.y, a.loaded.cloud.y);
    EXPECT_EQ(b.loaded.cloud.intensity, a.loaded.cloud.intensity);
    EXPECT_EQ(b.loaded.stats.valid_points, a.loaded.stats.valid_points);
    ++frames;
  }
  EXPECT_EQ(frames, 6u);
  EXPECT_FALSE(ahead->next(b));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace iilfm::io
