#include "iilfm/projection.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "fast_math.hpp"
#include "iilfm/error.hpp"
#include "iilfm/ring_structure.hpp"

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
  g.height =
      static_cast<int>(std::lround((bounds.elevation_max - bounds.elevation_min) / res_v)) + 1;
  return g;
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

void SphericalProjector::project(const PointView& cloud, ProjectedImage& out) {
  const std::size_t n = cloud.size();
  azimuth_.resize(n);
  elevation_.resize(n);
  range_.resize(n);

  // Pass 1: spherical coordinates (paper Eq. 1) and the cloud's angular extent, in a loop the
  // compiler can vectorise.
  const StridedColumn<float> xs = cloud.x, ys = cloud.y, zs = cloud.z;
  float az_min = 10, az_max = -10, el_min = 10, el_max = -10;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = xs[i], y = ys[i], z = zs[i];
    const float horizontal_sq = x * x + y * y;
    const float az = detail::fast_atan2(y, x);
    const float el = detail::fast_atan2(z, std::sqrt(horizontal_sq));
    azimuth_[i] = az;
    elevation_[i] = el;
    range_[i] = std::sqrt(horizontal_sq + z * z);
    az_min = std::min(az_min, az);
    az_max = std::max(az_max, az);
    el_min = std::min(el_min, el);
    el_max = std::max(el_max, el);
  }
  AngularBounds extent{az_min, az_max, el_min, el_max};
  if (n == 0) extent = AngularBounds{};

  AngularBounds bounds = extent;
  if (options_.field_of_view && inside(*options_.field_of_view, extent)) {
    bounds = *options_.field_of_view;
  }
  const double res_h = options_.res_h_deg * kDegToRad, res_v = options_.res_v_deg * kDegToRad;
  ImageGeometry g = geometry_for_bounds(bounds, res_h, res_v);

  // Ring rows: one row per laser, found from the ring field or the elevation clusters.
  std::optional<RingStructure> rings;
  if (options_.rows == RowLayout::kRings && n > 0) {
    rings = rings_from_field(cloud, elevation_.data());
    if (!rings) rings = rings_from_elevations(elevation_.data(), n);
  }
  out.row_source = rings ? rings->source : "uniform";
  if (rings) {
    g.height = static_cast<int>(rings->rows());
    g.row_elevation = rings->elevation;
    g.res_v = rings->rows() > 1 ? rings->mean_spacing() : res_v;
    g.v0 = 0;
  }

  const double pixels = static_cast<double>(g.width) * g.height;
  if (pixels > static_cast<double>(options_.max_pixels)) {
    throw InputError("intensity image would be " + std::to_string(g.width) + "x" +
                     std::to_string(g.height) + " pixels, over the limit of " +
                     std::to_string(options_.max_pixels) +
                     "; check --res-h/--res-v (degrees) or the sensor preset");
  }

  const std::size_t total = static_cast<std::size_t>(g.width) * g.height;
  pixels_.assign(total, PixelAccumulator{0.f, 0.f, std::numeric_limits<float>::max(), -1, 0});

  // Pass 2: bin every point (paper Eq. 2 with the non-mirrored orientation).
  const bool nearest = options_.collision == CollisionPolicy::kNearest;
  const float u0 = static_cast<float>(g.u0), v0 = static_cast<float>(g.v0);
  const float inv_res_h = static_cast<float>(1 / res_h), inv_res_v = static_cast<float>(1 / res_v);
  const float u_end = static_cast<float>(g.width) - 0.5f,
              v_end = static_cast<float>(g.height) - 0.5f;
  std::size_t projected = 0;
  auto accumulate = [&](std::size_t i, int col, int row, float offset) {
    PixelAccumulator& px = pixels_[static_cast<std::size_t>(row) * g.width + col];
    if (!nearest) {
      px.range_sum += range_[i];
      px.intensity_sum += cloud.intensity[i];
    } else if (px.count == 0 || range_[i] < px.range_sum) {
      px.range_sum = range_[i];
      px.intensity_sum = cloud.intensity[i];
    }
    if (offset < px.best_offset) {
      px.best_offset = offset;
      px.index = static_cast<std::int32_t>(i);
    }
    ++px.count;
    ++projected;
  };
  if (!rings) {
    for (std::size_t i = 0; i < n; ++i) {
      if (range_[i] <= 0) continue;
      const float u = u0 - azimuth_[i] * inv_res_h, v = v0 - elevation_[i] * inv_res_v;
      if (!(u >= -0.5f && v >= -0.5f && u < u_end && v < v_end)) continue;
      // Both are >= -0.5 here, so truncation of x + 0.5 rounds to nearest without a libm call.
      const int col = static_cast<int>(u + 0.5f), row = static_cast<int>(v + 0.5f);
      if (col >= g.width || row >= g.height) continue;
      const float du = u - static_cast<float>(col), dv = v - static_cast<float>(row);
      accumulate(i, col, row, du * du + dv * dv);
    }
  } else {
    // A ring is one row, so only the column offset decides which point represents the pixel.
    const bool by_field = !rings->row_of_ring.empty();
    const RingRowLookup lookup(by_field ? RingStructure{} : *rings);
    for (std::size_t i = 0; i < n; ++i) {
      if (range_[i] <= 0) continue;
      const float u = u0 - azimuth_[i] * inv_res_h;
      if (!(u >= -0.5f && u < u_end)) continue;
      const int col = static_cast<int>(u + 0.5f);
      if (col >= g.width) continue;
      int row;
      if (by_field) {
        const std::uint16_t ring = cloud.ring[i];
        row = ring < rings->row_of_ring.size() ? rings->row_of_ring[ring] : -1;
        if (row < 0) continue;
      } else {
        row = lookup.row(elevation_[i]);
      }
      const float du = u - static_cast<float>(col);
      accumulate(i, col, row, du * du);
    }
  }
  out.geometry = std::move(g);
  const ImageGeometry& geo = out.geometry;

  // Pass 3: the images, written sequentially.
  out.intensity.create(geo.height, geo.width, CV_32F);
  out.range.create(geo.height, geo.width, CV_32F);
  out.mask.create(geo.height, geo.width, CV_8U);
  out.index.create(geo.height, geo.width, CV_32S);
  out.count.create(geo.height, geo.width, CV_32S);
  float* intensity = out.intensity.ptr<float>();
  float* range = out.range.ptr<float>();
  std::uint8_t* mask = out.mask.ptr<std::uint8_t>();
  std::int32_t* index = out.index.ptr<std::int32_t>();
  std::int32_t* count = out.count.ptr<std::int32_t>();
  for (std::size_t p = 0; p < total; ++p) {
    const PixelAccumulator& px = pixels_[p];
    const float scale = (nearest || px.count <= 1) ? 1.0f : 1.0f / static_cast<float>(px.count);
    range[p] = px.range_sum * scale;
    intensity[p] = px.intensity_sum * scale;
    mask[p] = px.count > 0 ? 255 : 0;
    index[p] = px.index;
    count[p] = px.count;
  }
  out.points_projected = projected;
}

}  // namespace iilfm
