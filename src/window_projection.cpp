#include "iilfm/window_projection.hpp"

#include <algorithm>
#include <cstring>

#include "iilfm/error.hpp"
#include "projection_passes.hpp"

namespace iilfm {

namespace {
constexpr std::size_t kAhead = 16;  // points or pixels ahead whose sums are prefetched
}  // namespace

bool WindowProjector::supports(const ProjectionOptions& options) {
  return options.field_of_view && options.rows == RowLayout::kUniform;
}

WindowProjector::WindowProjector(ProjectionOptions options) : options_(std::move(options)) {
  if (!supports(options_))
    throw InputError("sliding-window projection needs a field of view and uniform rows");
  SphericalProjector check(options_);  // InputError for a bad resolution, as for one-shot frames
  constexpr double kDegToRad = M_PI / 180.0;
  geometry_ = geometry_for_bounds(*options_.field_of_view, options_.res_h_deg * kDegToRad,
                                  options_.res_v_deg * kDegToRad);
  require_image_within(geometry_, options_.max_pixels);
}

void WindowProjector::accumulate(const PointView& points, std::uint64_t first_id, int sign) {
  const std::size_t n = points.size();
  azimuth_.resize(n);
  elevation_.resize(n);
  range_.resize(n);
  pixel_.resize(n);
  detail::spherical_coordinates(points, azimuth_.data(), elevation_.data(), range_.data());
  const std::size_t outside =
      detail::pixels_of_points(geometry_, geometry_.width, azimuth_.data(), elevation_.data(),
                               range_.data(), n, pixel_.data());
  points_outside_ = sign > 0 ? points_outside_ + outside : points_outside_ - outside;
  points_inside_ = sign > 0 ? points_inside_ + (n - outside) : points_inside_ - (n - outside);
  const StridedColumn<float> intensity = points.intensity;
  for (std::size_t i = 0; i < n; ++i) {
    // A frame's points visit pixels all over the image (19 MB of sums for a Mid-40 image): the
    // sums of the point some places ahead are fetched while this one is added.
    if (i + kAhead < n) __builtin_prefetch(sums_.data() + std::max(pixel_[i + kAhead], 0), 1);
    const std::int32_t p = pixel_[i];
    if (p < 0) continue;
    PixelSums& s = sums_[static_cast<std::size_t>(p)];
    s.range += sign * static_cast<double>(range_[i]);
    s.intensity += sign * static_cast<double>(intensity[i]);
    s.ids += sign * static_cast<std::int64_t>(first_id + i);
    s.count += sign;
    touched_.push_back(p);
  }
}

void WindowProjector::write_pixel(std::size_t p, std::uint64_t first_id,
                                  ProjectedImage& out) const {
  const PixelSums& s = sums_[p];
  const bool observed = s.count > 0;
  const double scale = observed ? 1.0 / s.count : 0.0;
  out.intensity.ptr<float>()[p] = static_cast<float>(s.intensity * scale);
  out.range.ptr<float>()[p] = static_cast<float>(s.range * scale);
  out.mask.ptr<std::uint8_t>()[p] = observed ? 255 : 0;
  out.count.ptr<std::int32_t>()[p] = s.count;
  out.index.ptr<std::int32_t>()[p] =
      s.count == 1 ? static_cast<std::int32_t>(s.ids - static_cast<std::int64_t>(first_id)) : -1;
}

void WindowProjector::rebuild(const FrameWindow& window, ProjectedImage& out) {
  const std::size_t total = static_cast<std::size_t>(geometry_.width) * geometry_.height;
  sums_.resize(total);
  std::memset(static_cast<void*>(sums_.data()), 0, total * sizeof(PixelSums));
  points_outside_ = points_inside_ = 0;
  touched_.clear();
  accumulate(window.view(), window.first_point_id(), +1);
  out.geometry = geometry_;
  out.intensity.create(geometry_.height, geometry_.width, CV_32F);
  out.range.create(geometry_.height, geometry_.width, CV_32F);
  out.mask.create(geometry_.height, geometry_.width, CV_8U);
  out.index.create(geometry_.height, geometry_.width, CV_32S);
  out.count.create(geometry_.height, geometry_.width, CV_32S);
  for (std::size_t p = 0; p < total; ++p) write_pixel(p, window.first_point_id(), out);
}

void WindowProjector::project(const FrameWindow& window, ProjectedImage& out) {
  const bool next_push =
      &window == window_seen_ && pushes_seen_ > 0 && window.pushes() == pushes_seen_ + 1;
  if (!next_push || out.stamp != stamp_ || out.stamp == 0) {
    rebuild(window, out);
  } else {
    touched_.clear();
    const PointView dropped = window.dropped();
    if (!dropped.empty()) accumulate(dropped, window.first_point_id() - dropped.size(), -1);
    const PointView newest = window.newest();
    accumulate(newest, window.first_point_id() + (window.view().size() - newest.size()), +1);
    // Indices count from the window's first point, which moved by the dropped frame's size:
    // shift every single-point pixel's index, then rewrite the pixels that changed.
    if (!dropped.empty()) {
      std::int32_t* index = out.index.ptr<std::int32_t>();
      const std::int32_t shift = static_cast<std::int32_t>(dropped.size());
      const std::size_t total = out.index.total();
      for (std::size_t p = 0; p < total; ++p) index[p] = index[p] >= 0 ? index[p] - shift : -1;
    }
    for (std::size_t k = 0; k < touched_.size(); ++k) {
      if (k + kAhead < touched_.size()) __builtin_prefetch(sums_.data() + touched_[k + kAhead]);
      write_pixel(static_cast<std::size_t>(touched_[k]), window.first_point_id(), out);
    }
  }
  out.row_source = "uniform";
  out.column_offset.release();  // uniform rows
  out.points_projected = points_inside_;
  window_seen_ = &window;
  pushes_seen_ = window.pushes();
  out.stamp = stamp_ = next_projection_stamp();
}

}  // namespace iilfm
