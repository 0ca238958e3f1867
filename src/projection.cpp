#include "iilfm/projection.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "cpu_clones.hpp"
#include "iilfm/error.hpp"
#include "iilfm/ring_structure.hpp"
#include "lane_range.hpp"
#include "parallel_parts.hpp"
#include "projection_passes.hpp"
#include "ring_row_alignment.hpp"

namespace iilfm {

namespace {
constexpr double kDegToRad = M_PI / 180.0;
}

Vec2 ImageGeometry::pixel_of_point(const Vec3& p) const {
  return pixel_of_angles(std::atan2(p.y(), p.x()), std::atan2(p.z(), std::hypot(p.x(), p.y())));
}

double ImageGeometry::table_elevation_of_v(double v) const {
  const std::vector<double>& e = row_elevation;
  if (e.size() == 1) return e[0] - v * res_v;
  const double i = std::clamp(std::floor(v), 0.0, static_cast<double>(e.size() - 2));
  const std::size_t k = static_cast<std::size_t>(i);
  return e[k] + (v - i) * (e[k + 1] - e[k]);
}

double ImageGeometry::table_v_of_elevation(double elevation) const {
  const std::vector<double>& e = row_elevation;
  if (e.size() == 1) return (e[0] - elevation) / res_v;
  // First row whose elevation is below `elevation` (the table decreases), then the segment above
  // it.
  const auto below = std::upper_bound(e.begin(), e.end(), elevation, std::greater<double>());
  const std::size_t k =
      std::clamp<std::size_t>(static_cast<std::size_t>(below - e.begin()), 1, e.size() - 1) - 1;
  return static_cast<double>(k) + (elevation - e[k]) / (e[k + 1] - e[k]);
}

Vec3 ImageGeometry::ray(double u, double v) const {
  const double azimuth = azimuth_of_u(u);
  const double elevation = elevation_of_v(v);
  const double c = std::cos(elevation);
  return Vec3(c * std::cos(azimuth), c * std::sin(azimuth), std::sin(elevation));
}

std::uint64_t next_projection_stamp() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

AngularBounds angular_extent(const PointCloud& cloud) {
  AngularBounds b{std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                  std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest()};
  bool any = false;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const double x = cloud.x[i], y = cloud.y[i], z = cloud.z[i];
    if (x == 0 && y == 0 && z == 0) continue;
    const double az = std::atan2(y, x), el = std::atan2(z, std::hypot(x, y));
    b.azimuth_min = std::min(b.azimuth_min, az);
    b.azimuth_max = std::max(b.azimuth_max, az);
    b.elevation_min = std::min(b.elevation_min, el);
    b.elevation_max = std::max(b.elevation_max, el);
    any = true;
  }
  return any ? b : AngularBounds{};
}

ImageGeometry geometry_for_bounds(const AngularBounds& bounds, double res_h, double res_v) {
  ImageGeometry g;
  g.res_h = res_h;
  g.res_v = res_v;
  // The largest azimuth lands on column 0 and the largest elevation on row 0.
  g.u0 = bounds.azimuth_max / res_h;
  g.v0 = bounds.elevation_max / res_v;
  g.width = static_cast<int>(std::lround((bounds.azimuth_max - bounds.azimuth_min) / res_h)) + 1;
  // A cloud all round the sensor (a sweep from -180 to +180 deg, or a preset's full field) has one
  // turn of columns: one more would show the first column's direction again beside the seam, and
  // the samples there twice. Points past the last column wrap to the first (wrapping_columns).
  g.width = std::min(g.width, static_cast<int>(std::lround(g.columns_per_turn())));
  g.height =
      static_cast<int>(std::lround((bounds.elevation_max - bounds.elevation_min) / res_v)) + 1;
  return g;
}

void require_image_within(const ImageGeometry& g, std::size_t max_pixels) {
  const double pixels = static_cast<double>(g.width) * g.height;
  if (pixels > static_cast<double>(max_pixels)) {
    throw InputError("intensity image would be " + std::to_string(g.width) + "x" +
                     std::to_string(g.height) + " pixels, over the limit of " +
                     std::to_string(max_pixels) +
                     "; check --res-h/--res-v (degrees) or the sensor preset");
  }
}

SphericalProjector::SphericalProjector(ProjectionOptions options) : options_(std::move(options)) {
  if (!(options_.res_h_deg > 0) || !(options_.res_v_deg > 0) ||
      !std::isfinite(options_.res_h_deg) || !std::isfinite(options_.res_v_deg)) {
    throw InputError("angular resolution must be positive (got --res-h " +
                     std::to_string(options_.res_h_deg) + ", --res-v " +
                     std::to_string(options_.res_v_deg) + " deg)");
  }
}

namespace {
bool inside(const AngularBounds& outer, const AngularBounds& inner) {
  return inner.azimuth_min >= outer.azimuth_min && inner.azimuth_max <= outer.azimuth_max &&
         inner.elevation_min >= outer.elevation_min && inner.elevation_max <= outer.elevation_max;
}
}  // namespace

void SphericalProjector::project(const PointCloud& cloud, ProjectedImage& out) {
  project(PointView(cloud), out);
}

namespace {

// The extent in eight lanes (detail::LaneRange), with selects instead of a skip, so the loop
// vectorises.
IILFM_AVX2_CLONES AngularBounds extent_of(const float* __restrict azimuth,
                                          const float* __restrict elevation,
                                          const float* __restrict range, std::size_t n) {
  constexpr std::size_t kLanes = 8;
  detail::LaneRange<float, kLanes> az(10.0f, -10.0f), el(10.0f, -10.0f);
  const auto add = [&](std::size_t i, std::size_t j) {
    const bool measured = range[i] > 0;  // its angles are finite
    az.add(j, azimuth[i], measured);
    el.add(j, elevation[i], measured);
  };
  const std::size_t whole = n - n % kLanes;
  for (std::size_t i = 0; i < whole; i += kLanes)
    for (std::size_t j = 0; j < kLanes; ++j) add(i + j, j);
  for (std::size_t i = whole; i < n; ++i) add(i, 0);
  if (az.min() > az.max()) return AngularBounds{};
  return AngularBounds{az.min(), az.max(), el.min(), el.max()};
}

// Threads take at least this many points or pixels each (detail::parts_for).
constexpr std::size_t kMinPointsPerPart = 32768, kMinPixelsPerPart = 65536;
using detail::in_parts;
using detail::kMaxParts;
using detail::part_range;
using detail::parts_for;

// Points [begin, end) of `view`.
PointView slice(const PointView& view, std::size_t begin, std::size_t end) {
  PointView out = view;
  const auto from = static_cast<std::ptrdiff_t>(begin);
  out.x.data += from * view.x.stride;
  out.y.data += from * view.y.stride;
  out.z.data += from * view.z.stride;
  out.intensity.data += from * view.intensity.stride;
  if (view.ring) out.ring.data += from * view.ring.stride;
  out.count = end - begin;
  return out;
}

// `a` where `mask` is all ones, `b` where it is zero: a select the compiler cannot turn into a
// branch (bin_points' choices are as good as random, so a branch would be mispredicted often).
std::uint32_t masked_choice(std::uint32_t a, std::uint32_t b, std::uint32_t mask) {
  return b ^ ((a ^ b) & mask);
}
float masked_choice(float a, float b, std::uint32_t mask) {
  std::uint32_t a_bits, b_bits;
  std::memcpy(&a_bits, &a, sizeof a);
  std::memcpy(&b_bits, &b, sizeof b);
  const std::uint32_t bits = masked_choice(a_bits, b_bits, mask);
  float out;
  std::memcpy(&out, &bits, sizeof out);
  return out;
}

// Pass 3's input: each point's pixel (-1 outside the image), range and intensity.
struct PointsToBin {
  const std::int32_t* pixel;
  const float* range;
  StridedColumn<float> intensity;
  std::size_t n;
};

// Pass 3: bins the points whose pixel lies in [first, last) (paper Eq. 2, non-mirrored) and
// returns how many it binned. A pixel keeps the sums of its points and the index of the last one
// (lifting reads points only where a pixel has one); with kNearest, the range, intensity and
// index of its nearest point, chosen with masks (masked_choice): which point is nearest is as good
// as random, and a branch would be mispredicted often. The Livox rosette visits pixels in
// scattered order, so the pixel of the point some iterations ahead is prefetched and the misses
// overlap.
template <bool kNearest, bool kPrefetch, typename Accumulator>
std::size_t bin_points(const PointsToBin& points, std::size_t first, std::size_t last,
                       Accumulator* __restrict pixels) {
  const std::int32_t* __restrict pixel = points.pixel;
  const float* __restrict range = points.range;
  const float* __restrict intensity = points.intensity.data;
  const std::ptrdiff_t stride = points.intensity.stride;
  const std::size_t n = points.n;
  const auto lo = static_cast<std::int32_t>(first);
  const auto span = static_cast<std::uint32_t>(last - first);  // unsigned: -1 falls outside too
  const auto in_part = [&](std::int32_t p) { return static_cast<std::uint32_t>(p - lo) < span; };
  constexpr std::size_t kAhead = 32;
  std::size_t projected = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (kPrefetch && i + kAhead < n) {
      const std::int32_t ahead = pixel[i + kAhead];
      __builtin_prefetch(pixels + (in_part(ahead) ? ahead : lo), 1);
    }
    const std::int32_t p = pixel[i];
    if (!in_part(p)) continue;
    Accumulator& px = pixels[p];
    const float r = range[i], value = intensity[static_cast<std::ptrdiff_t>(i) * stride];
    const auto index = static_cast<std::int32_t>(i);
    if constexpr (kNearest) {
      const std::uint32_t nearer =
          0u - static_cast<std::uint32_t>((px.count == 0) | (r < px.range_sum));
      px.range_sum = masked_choice(r, px.range_sum, nearer);
      px.intensity_sum = masked_choice(value, px.intensity_sum, nearer);
      px.index = static_cast<std::int32_t>(masked_choice(
          static_cast<std::uint32_t>(index), static_cast<std::uint32_t>(px.index), nearer));
    } else {
      px.range_sum += r;
      px.intensity_sum += value;
      px.index = index;
    }
    ++px.count;
    ++projected;
  }
  return projected;
}

// Written so that GCC 12 vectorises it (it was scalar before: 5 ms of a 600k-point Mid-40
// projection): restrict pointers, a loop-invariant policy, unsigned comparisons of the count and
// a signed conversion to float (a signed comparison alone kept it scalar).
template <typename Accumulator>
void write_block(const Accumulator* __restrict pixels, std::size_t n, bool nearest,
                 float* __restrict range, float* __restrict intensity,
                 std::uint8_t* __restrict mask, std::int32_t* __restrict index,
                 std::int32_t* __restrict count) {
  for (std::size_t p = 0; p < n; ++p) {
    const Accumulator& px = pixels[p];
    // Counts lie below 2^31 (points are indexed by int32); saying so keeps the loop vectorised.
    const std::uint32_t n_px = px.count & 0x7fffffffu;
    const auto n_signed = static_cast<std::int32_t>(n_px);
    const float scale = (nearest || n_px <= 1) ? 1.0f : 1.0f / static_cast<float>(n_signed);
    range[p] = px.range_sum * scale;
    intensity[p] = px.intensity_sum * scale;
    mask[p] = n_px > 0 ? 255 : 0;
    index[p] = n_px > 0 ? px.index : -1;
    count[p] = n_signed;
  }
}
}  // namespace

std::size_t SphericalProjector::accumulator_row_stride(int width) {
  constexpr std::size_t kPerLine = 64 / sizeof(PixelAccumulator);
  const std::size_t lines = (static_cast<std::size_t>(width) + kPerLine - 1) / kPerLine;
  return (lines | 1) * kPerLine;
}

IILFM_AVX2_CLONES void SphericalProjector::write_images(PixelAccumulator* pixels, int first_row,
                                                        int end_row, int width, std::size_t stride,
                                                        bool nearest, float* range,
                                                        float* intensity, std::uint8_t* mask,
                                                        std::int32_t* index, std::int32_t* count) {
  // Block by block, clearing each block for the next frame while it is still in L1: cheaper than
  // a separate pass over the whole array (9 MB for a Mid-40 image). Padding is never binned.
  constexpr std::size_t kBlock = 1024;
  const auto w = static_cast<std::size_t>(width);
  for (int row = first_row; row < end_row; ++row) {
    PixelAccumulator* accumulators = pixels + static_cast<std::size_t>(row) * stride;
    const std::size_t out = static_cast<std::size_t>(row) * w;
    for (std::size_t begin = 0; begin < w; begin += kBlock) {
      const std::size_t n = std::min(kBlock, w - begin);
      const std::size_t at = out + begin;
      write_block(accumulators + begin, n, nearest, range + at, intensity + at, mask + at,
                  index + at, count + at);
      std::memset(static_cast<void*>(accumulators + begin), 0, n * sizeof(PixelAccumulator));
    }
  }
}

void SphericalProjector::project(const PointView& cloud, ProjectedImage& out) {
  const std::size_t n = cloud.size();
  azimuth_.resize(n);
  elevation_.resize(n);
  range_.resize(n);
  pixel_.resize(n);

  const int point_parts = parts_for(options_.threads, n, kMinPointsPerPart);
  in_parts(point_parts, [&](int k, int parts) {
    const auto [begin, end] = part_range(n, k, parts);
    detail::spherical_coordinates(slice(cloud, begin, end), azimuth_.data() + begin,
                                  elevation_.data() + begin, range_.data() + begin);
  });
  // Pass 2 for uniform rows, in parts like pass 1; returns the points outside the image.
  const auto pixels_in_parts = [&](const ImageGeometry& geometry) {
    std::size_t outside[kMaxParts] = {};
    in_parts(point_parts, [&](int k, int parts) {
      const auto [begin, end] = part_range(n, k, parts);
      outside[k] = detail::pixels_of_points(
          geometry, static_cast<std::int32_t>(accumulator_row_stride(geometry.width)),
          azimuth_.data() + begin, elevation_.data() + begin, range_.data() + begin, end - begin,
          pixel_.data() + begin);
    });
    std::size_t sum = 0;
    for (int k = 0; k < point_parts; ++k) sum += outside[k];
    return sum;
  };

  const double res_h = options_.res_h_deg * kDegToRad, res_v = options_.res_v_deg * kDegToRad;
  // Ring rows: one row per laser, found from the ring field or the elevation clusters.
  std::optional<RingStructure> rings;
  if (options_.rows == RowLayout::kRings && n > 0) {
    rings = rings_from_field(cloud, elevation_.data());
    if (!rings) rings = rings_from_elevations(elevation_.data(), n);
  }
  out.row_source = rings ? rings->source : "uniform";

  // The sensor's field of view when the cloud lies inside it (the common case: then the extent
  // is never computed, the count of points outside says so); otherwise the cloud's own extent.
  auto geometry_for = [&](const AngularBounds& bounds) {
    ImageGeometry g = geometry_for_bounds(bounds, res_h, res_v);
    if (rings) {
      g.height = static_cast<int>(rings->rows());
      g.row_elevation = rings->elevation;
      g.res_v = rings->rows() > 1 ? rings->mean_spacing() : res_v;
      g.v0 = 0;
    }
    require_image_within(g, options_.max_pixels);
    return g;
  };
  auto extent = [&] { return extent_of(azimuth_.data(), elevation_.data(), range_.data(), n); };
  ImageGeometry g;
  if (!rings) {
    bool placed = false;
    if (options_.field_of_view) {
      g = geometry_for(*options_.field_of_view);
      const std::size_t outside = pixels_in_parts(g);
      // Points outside the field of view that were measured: the preset does not fit the cloud.
      std::size_t unmeasured = 0;
      if (outside > 0)
        for (std::size_t i = 0; i < n; ++i) unmeasured += range_[i] > 0 ? 0 : 1;
      placed = outside == unmeasured;
    }
    if (!placed) {
      g = geometry_for(extent());
      pixels_in_parts(g);
    }
  } else {
    const AngularBounds cloud_extent = extent();
    g = geometry_for(options_.field_of_view && inside(*options_.field_of_view, cloud_extent)
                         ? *options_.field_of_view
                         : cloud_extent);
    const bool by_field = !rings->row_of_ring.empty();
    const RingRowLookup lookup(by_field ? RingStructure{} : *rings);
    const float u0 = static_cast<float>(g.u0), inv_res_h = static_cast<float>(1 / res_h);
    const float u_end = static_cast<float>(g.width) - 0.5f;
    const float wrap = static_cast<float>(g.wrapping_columns());
    const auto row_stride = static_cast<int>(accumulator_row_stride(g.width));
    if (by_field) {
      const std::uint16_t* ring = cloud.ring.data;
      if (cloud.ring.stride != 1) {  // a numpy record array's field: copied, to vectorise
        ring_copy_.resize(n);
        for (std::size_t i = 0; i < n; ++i) ring_copy_[i] = cloud.ring[i];
        ring = ring_copy_.data();
      }
      detail::ring_pixels_of_points(g, row_stride, rings->row_of_ring.data(),
                                    rings->row_of_ring.size(), ring, azimuth_.data(), range_.data(),
                                    n, pixel_.data());
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        pixel_[i] = -1;
        if (!(range_[i] > 0)) continue;
        float u = u0 - azimuth_[i] * inv_res_h;
        if (u >= u_end) u -= wrap;  // past a full circle's last column: the first one's
        if (!(u >= -0.5f && u < u_end)) continue;
        const int col = static_cast<int>(u + 0.5f);
        if (col >= g.width) continue;
        pixel_[i] = lookup.row(elevation_[i]) * row_stride + col;
      }
    }
  }

  // Pass 3 (bin_points).
  const std::size_t stride = accumulator_row_stride(g.width);
  const std::size_t total = stride * static_cast<std::size_t>(g.height);
  // Pass 4 clears every accumulator it reads, which saves a separate pass over them; only a frame
  // that stopped between the passes (an exception) leaves them to be cleared here.
  if (!pixels_clear_)
    std::memset(static_cast<void*>(pixels_.data()), 0, pixels_.size() * sizeof(PixelAccumulator));
  pixels_.resize(total);
  pixels_clear_ = false;
  const bool nearest = options_.collision == CollisionPolicy::kNearest;
  // Accumulators that fit in L2 (a spinning LiDAR's ring rows: 0.5 MB for a VLP-16) stay there
  // between points; prefetching them is only overhead.
  constexpr std::size_t kPrefetchAboveBytes = std::size_t{1} << 20;
  const bool prefetch = total * sizeof(PixelAccumulator) > kPrefetchAboveBytes;
  // With threads, each takes a range of pixels and reads every point, binning those that fall in
  // its range: a pixel's points are still added in the cloud's order, by one thread.
  const int pixel_parts =
      std::min(parts_for(options_.threads, total, kMinPixelsPerPart), point_parts);
  std::size_t projected_in[kMaxParts] = {};
  in_parts(pixel_parts, [&](int k, int parts) {
    const auto [first, last] = part_range(total, k, parts);
    const PointsToBin points{pixel_.data(), range_.data(), cloud.intensity, n};
    projected_in[k] =
        nearest ? (prefetch ? bin_points<true, true>(points, first, last, pixels_.data())
                            : bin_points<true, false>(points, first, last, pixels_.data()))
                : (prefetch ? bin_points<false, true>(points, first, last, pixels_.data())
                            : bin_points<false, false>(points, first, last, pixels_.data()));
  });
  std::size_t projected = 0;
  for (int k = 0; k < pixel_parts; ++k) projected += projected_in[k];
  out.geometry = std::move(g);
  const ImageGeometry& geo = out.geometry;

  // Pass 4: the images, written sequentially.
  out.intensity.create(geo.height, geo.width, CV_32F);
  out.range.create(geo.height, geo.width, CV_32F);
  out.mask.create(geo.height, geo.width, CV_8U);
  out.index.create(geo.height, geo.width, CV_32S);
  out.count.create(geo.height, geo.width, CV_32S);
  detail::in_row_parts(geo.height, parts_for(options_.threads, total, kMinPixelsPerPart),
                       [&](int first_row, int end_row) {
                         write_images(pixels_.data(), first_row, end_row, geo.width, stride,
                                      nearest, out.range.ptr<float>(), out.intensity.ptr<float>(),
                                      out.mask.ptr<std::uint8_t>(), out.index.ptr<std::int32_t>(),
                                      out.count.ptr<std::int32_t>());
                       });
  pixels_clear_ = true;
  if (rings && options_.column_offsets)
    detail::measure_column_offsets(azimuth_.data(), out);
  else
    out.column_offset.release();
  out.points_projected = projected;
  out.stamp = next_projection_stamp();
}

}  // namespace iilfm
