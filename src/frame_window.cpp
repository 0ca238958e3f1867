#include "iilfm/frame_window.hpp"

#include <algorithm>

namespace iilfm {
namespace {

template <typename T>
void append(std::vector<T>& into, const std::vector<T>& from) {
  into.insert(into.end(), from.begin(), from.end());
}

}  // namespace

FrameWindow::FrameWindow(std::size_t frames) : capacity_(std::max<std::size_t>(frames, 1)) {}

void FrameWindow::push(PointCloud cloud, const CloudStats& stats) {
  if (frames_.size() == capacity_) frames_.pop_front();
  frames_.push_back({std::move(cloud), stats});
  merged_valid_ = false;
}

const PointCloud& FrameWindow::cloud() {
  if (frames_.size() == 1) return frames_.front().cloud;
  if (merged_valid_) return merged_;
  std::size_t total = 0;
  bool with_ring = true, with_time = true;
  for (const Held& f : frames_) {
    total += f.cloud.size();
    with_ring = with_ring && (f.cloud.has_ring() || f.cloud.empty());
    with_time = with_time && (f.cloud.has_time() || f.cloud.empty());
  }
  merged_.clear();  // keeps the capacity: no reallocation once the window has filled
  merged_.reserve(total, with_ring, with_time);
  for (const Held& f : frames_) {
    append(merged_.x, f.cloud.x);
    append(merged_.y, f.cloud.y);
    append(merged_.z, f.cloud.z);
    append(merged_.intensity, f.cloud.intensity);
    if (with_ring) append(merged_.ring, f.cloud.ring);
    if (with_time) append(merged_.time, f.cloud.time);
  }
  merged_valid_ = true;
  return merged_;
}

CloudStats FrameWindow::stats() const {
  CloudStats sum;
  for (const Held& f : frames_) {
    sum.points_in_file += f.stats.points_in_file;
    sum.valid_points += f.stats.valid_points;
    sum.non_finite += f.stats.non_finite;
    sum.zero += f.stats.zero;
  }
  return sum;
}

}  // namespace iilfm
