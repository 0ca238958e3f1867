// The last N frames of a recording and their union: the cloud the pipeline sees when frames are
// integrated (Livox sensors need several to cover a marker). The window slides by one frame per
// push. Its points live in one buffer, oldest first, so the union is a view, never a
// concatenation; the frame a push drops stays readable until the next push, so an incremental
// projection can subtract it (Pipeline::process(const FrameWindow&)).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>

#include "iilfm/types.hpp"

namespace iilfm {

class FrameWindow {
 public:
  explicit FrameWindow(std::size_t frames);  // at least 1
  // A time window (`--window-seconds`): the frames taken less than `seconds` before the newest
  // one, however many. InputError unless seconds is positive and finite.
  static FrameWindow over_seconds(double seconds);

  // Adds the newest frame, taken at `stamp_s` seconds; drops the oldest once the window holds N
  // frames, or, for a time window, every frame at least `seconds` older than this one (a push
  // may then drop several frames, or none). A time window needs finite stamps (InputError).
  void push(const PointCloud& cloud, const CloudStats& stats, double stamp_s = 0);
  // N frames held, or, for a time window, frames spanning the window: the newest stamp minus the
  // oldest plus one frame interval (the newest gap) reaches `seconds`; then it stays full.
  bool full() const { return seconds_ > 0 ? spanned_ : frames_.size() == capacity_; }
  std::size_t size() const { return frames_.size(); }
  std::size_t capacity() const { return capacity_; }  // the largest count held (time: unbounded)
  double seconds() const { return seconds_; }         // 0 for a frame-count window

  // The union of the frames held, oldest first (ring kept when every frame has it), valid until
  // the next push.
  PointView view() const { return view_of(begin_, end_); }
  // The newest frame, and the frame the last push dropped (empty if none), as views.
  PointView newest() const {
    return frames_.empty() ? PointView{} : view_of(end_ - frames_.back().points, end_);
  }
  PointView dropped() const { return view_of(begin_ - dropped_points_, begin_); }
  // Every point pushed gets the next running id; the window's oldest point has this one.
  std::uint64_t first_point_id() const { return dropped_total_; }
  // Pushes so far: a consumer that saw push k can update incrementally at push k + 1.
  std::uint64_t pushes() const { return pushes_; }
  // The union copied into a cloud of its own (ring and time kept when every frame has them).
  PointCloud copy() const;
  // The frames' statistics summed.
  CloudStats stats() const;

 private:
  struct Held {
    std::size_t points;
    CloudStats stats;
    bool ring, time;
    double stamp_s;
  };
  PointView view_of(std::size_t begin, std::size_t end) const;
  void make_room(std::size_t points);
  void drop_oldest();

  std::size_t capacity_;
  std::deque<Held> frames_;
  PointCloud buffer_;  // [begin_ - dropped_points_, end_) is live; the rest is free space
  std::size_t begin_ = 0, end_ = 0, dropped_points_ = 0;
  std::uint64_t pushes_ = 0;
  std::uint64_t dropped_total_ = 0;  // points dropped by all pushes so far
  double seconds_ = 0;               // > 0: a time window
  bool spanned_ = false;
};

}  // namespace iilfm
