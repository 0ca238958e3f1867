#include "iilfm/frame_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "iilfm/error.hpp"

namespace iilfm {
namespace {

template <typename T>
void move_to_front(std::vector<T>& column, std::size_t from, std::size_t to) {
  to = std::min(to, column.size());  // ring and time columns may stop early (frames without them)
  if (from < to) std::copy(column.begin() + from, column.begin() + to, column.begin());
}

template <typename T>
void put(std::vector<T>& column, std::size_t at, const std::vector<T>& values) {
  if (column.size() < at + values.size()) column.resize(at + values.size());
  std::copy(values.begin(), values.end(), column.begin() + at);
}

}  // namespace

FrameWindow::FrameWindow(std::size_t frames) : capacity_(std::max<std::size_t>(frames, 1)) {}

FrameWindow FrameWindow::over_seconds(double seconds) {
  if (!(seconds > 0) || !std::isfinite(seconds))
    throw InputError("--window-seconds must be a positive number of seconds, got " +
                     std::to_string(seconds));
  FrameWindow window(std::numeric_limits<std::size_t>::max());
  window.seconds_ = seconds;
  return window;
}

void FrameWindow::drop_oldest() {
  dropped_points_ += frames_.front().points;
  dropped_total_ += frames_.front().points;
  begin_ += frames_.front().points;
  frames_.pop_front();
}

// Keeps the buffer's live part (the window and the frame dropped last) at its front when the free
// space behind it runs out, and sizes the buffer to twice the live part: each point is then moved
// about once per window length, not once per push.
void FrameWindow::make_room(std::size_t points) {
  std::vector<float>* columns[] = {&buffer_.x, &buffer_.y, &buffer_.z, &buffer_.intensity};
  if (end_ + points <= buffer_.x.size()) return;
  const std::size_t live_begin = begin_ - dropped_points_;
  for (std::vector<float>* c : columns) move_to_front(*c, live_begin, end_);
  move_to_front(buffer_.ring, live_begin, end_);
  move_to_front(buffer_.time, live_begin, end_);
  begin_ -= live_begin;
  end_ -= live_begin;
  // Grown to twice the live part whenever it is smaller, not only when the frame does not fit:
  // a buffer a little larger than the window moved the whole window every few pushes (a 60-frame
  // Mid-40 window: 10 MB every second or third push).
  const std::size_t wanted = 2 * (end_ + points);
  if (buffer_.x.size() < wanted)
    for (std::vector<float>* c : columns) c->resize(wanted);
}

void FrameWindow::push(const PointCloud& cloud, const CloudStats& stats, double stamp_s) {
  if (seconds_ > 0 && !std::isfinite(stamp_s))
    throw InputError("a --window-seconds window needs finite frame stamps");
  ++pushes_;
  dropped_points_ = 0;
  if (frames_.size() == capacity_) drop_oldest();
  const std::size_t n = cloud.size();
  make_room(n);
  put(buffer_.x, end_, cloud.x);
  put(buffer_.y, end_, cloud.y);
  put(buffer_.z, end_, cloud.z);
  put(buffer_.intensity, end_, cloud.intensity);
  put(buffer_.ring, end_, cloud.ring);  // no-op for a frame without rings (then never exposed)
  put(buffer_.time, end_, cloud.time);
  end_ += n;
  frames_.push_back({n, stats, cloud.has_ring() || n == 0, cloud.has_time() || n == 0, stamp_s});
  if (seconds_ > 0) {
    // Tolerance for stamps written in decimal: 10 Hz frames over 1 s are 10 frames, not 11.
    constexpr double kSlack = 1e-6;
    const double oldest_kept = stamp_s - seconds_ + kSlack;
    bool dropped = false;
    while (frames_.size() > 1 && frames_.front().stamp_s < oldest_kept) {
      drop_oldest();
      dropped = true;
    }
    if (frames_.size() >= 2) {
      const double interval = stamp_s - frames_[frames_.size() - 2].stamp_s;
      spanned_ =
          spanned_ || dropped || stamp_s - frames_.front().stamp_s + interval >= seconds_ - kSlack;
    } else {
      spanned_ = spanned_ || dropped;
    }
  }
}

PointView FrameWindow::view_of(std::size_t begin, std::size_t end) const {
  PointView v;
  v.count = end - begin;
  if (buffer_.x.empty()) return v;
  v.x = {buffer_.x.data() + begin, 1};
  v.y = {buffer_.y.data() + begin, 1};
  v.z = {buffer_.z.data() + begin, 1};
  v.intensity = {buffer_.intensity.data() + begin, 1};
  const bool ring =
      std::all_of(frames_.begin(), frames_.end(), [](const Held& f) { return f.ring; });
  if (ring) v.ring = {buffer_.ring.data() + begin, 1};
  return v;
}

PointCloud FrameWindow::copy() const {
  PointCloud out;
  const bool ring =
      std::all_of(frames_.begin(), frames_.end(), [](const Held& f) { return f.ring; });
  const bool time =
      std::all_of(frames_.begin(), frames_.end(), [](const Held& f) { return f.time; });
  auto slice = [&](const auto& column, auto& into) {
    into.assign(column.begin() + begin_, column.begin() + end_);
  };
  if (end_ == begin_) return out;
  slice(buffer_.x, out.x);
  slice(buffer_.y, out.y);
  slice(buffer_.z, out.z);
  slice(buffer_.intensity, out.intensity);
  if (ring) slice(buffer_.ring, out.ring);
  if (time) slice(buffer_.time, out.time);
  return out;
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
