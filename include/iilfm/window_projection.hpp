// Sliding-window projection: keeps per-pixel sums over the frames of a FrameWindow, so each push
// adds the newest frame's points, subtracts the dropped frame's and rewrites only the pixels they
// touch, instead of re-projecting the whole window (a 60-frame Mid-40 window: 20k points per push
// instead of 600k). The image is the same as SphericalProjector's for the window's points, except
// that `index` is -1 where several points share a pixel (a sum of ids identifies a pixel's point
// only when it holds one; lifting uses points only there).
#pragma once

#include <cstdint>
#include <vector>

#include "iilfm/frame_window.hpp"
#include "iilfm/projection.hpp"

namespace iilfm {

class WindowProjector {
 public:
  // The image must be fixed for sums to carry over: a field of view and uniform rows (the Livox
  // presets). Spinning LiDARs integrate one sweep and use SphericalProjector.
  static bool supports(const ProjectionOptions& options);
  explicit WindowProjector(ProjectionOptions options);  // InputError when !supports(options)

  // Brings `out` up to date with `window`: incrementally when it is the window of the last call,
  // moved by one push since, and `out` still holds this projector's output; otherwise from
  // scratch. Points
  // outside the field of view are left out (points_outside counts them).
  void project(const FrameWindow& window, ProjectedImage& out);
  std::size_t points_outside() const { return points_outside_; }

 private:
  struct PixelSums {
    double range, intensity;
    std::int64_t ids;  // sum of the points' running ids: the id itself when count == 1
    std::int32_t count, unused;
  };

  // Adds (sign +1) or removes (sign -1) `points`, whose first running id is `first_id`, and
  // appends the pixels they touch to touched_.
  void accumulate(const PointView& points, std::uint64_t first_id, int sign);
  void write_pixel(std::size_t p, std::uint64_t first_id, ProjectedImage& out) const;
  void rebuild(const FrameWindow& window, ProjectedImage& out);

  ProjectionOptions options_;
  ImageGeometry geometry_;
  std::vector<PixelSums, detail::HugePageAllocator<PixelSums>> sums_;  // scattered: huge pages
  std::vector<float> azimuth_, elevation_, range_;
  std::vector<std::int32_t> pixel_, touched_;
  const FrameWindow* window_seen_ = nullptr;  // the window the sums follow
  std::uint64_t pushes_seen_ = 0, stamp_ = 0;
  std::size_t points_outside_ = 0, points_inside_ = 0;
};

}  // namespace iilfm
