// Frame after frame of the same sensor, projection and preprocessing reuse their buffers: no heap
// allocation at all once warm (counted through operator new and OpenCV's matrix allocator).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <opencv2/core.hpp>
#include <random>

#include "iilfm/pipeline.hpp"
#include "iilfm/preprocess.hpp"
#include "iilfm/projection.hpp"
#include "iilfm/sensor.hpp"
#include "synthetic_frames.hpp"

namespace {
std::atomic<long> g_new_calls{0};
}  // namespace

// Counts every operator new in this test program (the library's std containers allocate through
// it); the test reads the count around the calls it checks. Every plain and nothrow form is
// replaced, so each allocation is released by its own kind (AddressSanitizer checks the pairing).
namespace {
void* counted_allocation(std::size_t size) {
  ++g_new_calls;
  return std::malloc(size ? size : 1);
}
}  // namespace

void* operator new(std::size_t size) {
  if (void* p = counted_allocation(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = counted_allocation(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return counted_allocation(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return counted_allocation(size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace iilfm {
namespace {

// Wraps OpenCV's default matrix allocator, counting allocations.
class CountingMatAllocator : public cv::MatAllocator {
 public:
  explicit CountingMatAllocator(cv::MatAllocator* inner) : inner_(inner) {}
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step,
                         cv::AccessFlag flags, cv::UMatUsageFlags usage) const override {
    ++allocations;
    return inner_->allocate(dims, sizes, type, data, step, flags, usage);
  }
  bool allocate(cv::UMatData* data, cv::AccessFlag flags, cv::UMatUsageFlags usage) const override {
    return inner_->allocate(data, flags, usage);
  }
  void deallocate(cv::UMatData* data) const override { inner_->deallocate(data); }
  mutable std::atomic<long> allocations{0};

 private:
  cv::MatAllocator* inner_;
};

struct Allocations {
  long news = 0, mats = 0;
};

// Allocations of projection and preprocessing over frames after the first, with the preset's
// fixed threshold or the local one.
void expect_no_allocation_once_warm(bool local_threshold) {
  // Declared first: matrices allocated through it release through it, so it must outlive them.
  cv::MatAllocator* const standard = cv::Mat::getDefaultAllocator();
  CountingMatAllocator counting(standard);
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid40"), options);
  options.preprocess.local_threshold = local_threshold;
  SphericalProjector projector(options.projection);
  ProjectedImage image;
  PreprocessedImage pre;
  cv::Mat::setDefaultAllocator(&counting);

  // Frames of different sizes, as a real sensor delivers: the buffers grow to the largest once.
  std::vector<PointCloud> frames;
  for (std::uint32_t seed = 1; seed <= 4; ++seed)
    frames.push_back(testing::livox_like_frame(seed, 20000 + 1000 * seed));
  auto run = [&](const PointCloud& frame) {
    const long news = g_new_calls.load(), mats = counting.allocations.load();
    projector.project(frame, image);
    preprocess(image, options.preprocess, pre);
    return Allocations{g_new_calls.load() - news, counting.allocations.load() - mats};
  };
  const Allocations first = run(frames.back());  // the largest frame first
  std::vector<Allocations> later;
  for (const PointCloud& frame : frames) later.push_back(run(frame));
  cv::Mat::setDefaultAllocator(standard);

  EXPECT_GT(first.news + first.mats, 0) << "the counters see the first frame's allocations";
  for (std::size_t i = 0; i < later.size(); ++i) {
    EXPECT_EQ(later[i].news, 0) << "frame " << i;
    EXPECT_EQ(later[i].mats, 0) << "frame " << i;
  }
  EXPECT_GT(cv::countNonZero(pre.detect), 0);
}

TEST(SteadyState, ProjectionAndPreprocessingAllocateNothingOnceWarm) {
  expect_no_allocation_once_warm(false);
}

// The local threshold's window sums live in buffers kept across frames (as temporaries they cost
// a Mid-40 image 15 ms of first touches a frame).
TEST(SteadyState, TheLocalThresholdAllocatesNothingOnceWarm) {
  expect_no_allocation_once_warm(true);
}

}  // namespace
}  // namespace iilfm
