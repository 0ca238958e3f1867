// The last N frames of a recording and their union: the cloud the pipeline sees when frames are
// integrated (Livox sensors need several to cover a marker). The window slides by one frame per
// push. Today the union is rebuilt by concatenation after each push; an incremental projection can
// replace that behind this interface.
#pragma once

#include <cstddef>
#include <deque>

#include "iilfm/types.hpp"

namespace iilfm {

class FrameWindow {
 public:
  explicit FrameWindow(std::size_t frames);  // at least 1

  // Adds the newest frame; drops the oldest once the window holds N frames.
  void push(PointCloud cloud, const CloudStats& stats);
  bool full() const { return frames_.size() == capacity_; }
  std::size_t size() const { return frames_.size(); }
  std::size_t capacity() const { return capacity_; }

  // The union of the frames held, oldest first. Ring and time are kept when every frame has them.
  const PointCloud& cloud();
  // The frames' statistics summed.
  CloudStats stats() const;

 private:
  struct Held {
    PointCloud cloud;
    CloudStats stats;
  };
  std::size_t capacity_;
  std::deque<Held> frames_;
  PointCloud merged_;
  bool merged_valid_ = false;
};

}  // namespace iilfm
