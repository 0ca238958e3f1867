#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "iilfm/lift.hpp"
#include "iilfm/square_pixels.hpp"
#include "parallel_parts.hpp"
#include "plane_fit_passes.hpp"

namespace iilfm {

namespace {

// Sums of a point set's coordinates and of their products (detail::CoordinateSums), about a
// reference point near the points (so the one-pass scatter keeps its precision).
struct Moments : detail::CoordinateSums {
  Vec3 ref = Vec3::Zero();

  Moments() = default;
  Moments(const detail::CoordinateSums& sums, const Vec3& about)
      : detail::CoordinateSums(sums), ref(about) {}

  // Adds (sign 1) or removes (sign -1) another set summed about the same reference point.
  void merge(const Moments& o, double sign) {
    n += sign * o.n;
    x += sign * o.x;
    y += sign * o.y;
    z += sign * o.z;
    xx += sign * o.xx;
    xy += sign * o.xy;
    xz += sign * o.xz;
    yy += sign * o.yy;
    yz += sign * o.yz;
    zz += sign * o.zz;
  }
};

// Least-squares plane through the points summed in `m` (smallest principal axis of their
// scatter), without its uncertainty (add_plane_uncertainty): the robust fit's intermediate planes
// do not need it.
Plane plane_from_moments(const Moments& m) {
  Plane plane;
  if (m.n < 3) return plane;
  const double mx = m.x / m.n, my = m.y / m.n, mz = m.z / m.n;
  Mat3 scatter;
  scatter << m.xx - m.n * mx * mx, m.xy - m.n * mx * my, m.xz - m.n * mx * mz,  //
      m.xy - m.n * mx * my, m.yy - m.n * my * my, m.yz - m.n * my * mz,         //
      m.xz - m.n * mx * mz, m.yz - m.n * my * mz, m.zz - m.n * mz * mz;
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  // The two larger spreads must be real: a row of points does not define a plane.
  if (!(eig.eigenvalues()(1) > 1e-12)) return plane;
  const Vec3 centre = m.ref + Vec3(mx, my, mz);
  plane.normal = eig.eigenvectors().col(0);
  if (plane.normal.dot(centre) > 0) plane.normal = -plane.normal;  // face the sensor
  plane.d = plane.normal.dot(centre);
  plane.centre = centre;
  plane.axis1 = eig.eigenvectors().col(1);
  plane.axis2 = eig.eigenvectors().col(2);
  plane.inliers = static_cast<std::size_t>(m.n);
  plane.ok = true;
  return plane;
}

// Slope variances of `plane` by a block jackknife: the inliers split into kGrid x kGrid patches
// along the plane's axes (extent: x1 from, to, x2 from, to about the centre), the plane refitted
// without each patch in turn. Range errors correlated between neighbouring points tilt the fit
// more than independent residuals can say; the patches' spread shows it. Zero when fewer than 6
// patches hold points.
Eigen::Vector2d jackknife_slope_variance(const detail::FitPoints& fit, const Plane& plane,
                                         const double extent[4]) {
  constexpr int kGrid = 4;
  std::array<Moments, kGrid * kGrid> patches;
  for (Moments& m : patches) m.ref = plane.centre;
  thread_local std::vector<std::int32_t> patch;
  patch.resize(fit.size());
  detail::grid_patches(fit, plane.centre, plane.axis1, plane.axis2, extent, kGrid, patch.data());
  // Points come row by row, so runs of them fall in one patch: each run is summed in vector lanes
  // and added to its patch's sums.
  for (std::size_t k = 0; k < fit.size();) {
    const std::int32_t id = patch[k];
    std::size_t end = k + 1;
    while (end < fit.size() && patch[end] == id) ++end;
    patches[static_cast<std::size_t>(id)].merge(
        Moments(detail::coordinate_sums(fit, plane.centre, k, end), plane.centre), 1);
    k = end;
  }
  Moments total;
  total.ref = plane.centre;
  for (const Moments& patch : patches) total.merge(patch, 1);
  std::array<Eigen::Vector2d, kGrid * kGrid> slopes;
  std::size_t k = 0;
  for (const Moments& patch : patches) {
    if (patch.n < 1) continue;
    Moments rest_moments = total;
    rest_moments.merge(patch, -1);
    const Plane rest = plane_from_moments(rest_moments);
    const double along = rest.normal.dot(plane.normal);
    if (!rest.ok || std::abs(along) < 0.5) continue;
    slopes[k++] =
        Eigen::Vector2d(-rest.normal.dot(plane.axis1), -rest.normal.dot(plane.axis2)) / along;
  }
  if (k < 6) return Eigen::Vector2d::Zero();
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < k; ++i) mean += slopes[i];
  mean /= static_cast<double>(k);
  Eigen::Vector2d spread = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < k; ++i) spread += (slopes[i] - mean).cwiseAbs2();
  return spread * (static_cast<double>(k) - 1) / static_cast<double>(k);
}

// The fitted plane's RMS residual and uncertainty, from the residuals themselves
// (heteroscedasticity-consistent, White's sandwich): the points are not equally noisy (a pixel's
// point may be the mean of several returns, and a rosette is densest at its centre), so the far,
// sparse points that fix the slope must count with their own scatter. Scaled by n / (n - 3) for
// the 3 fitted parameters. A slope's variance is the larger of that and the block jackknife's
// (measured on the multi-marker scenes: the sandwich alone claimed 1.3 mrad where the normals were
// 1.9 mrad off per axis, the jackknife 1.8).
void add_plane_uncertainty(const detail::FitPoints& fit, Plane& plane) {
  if (!plane.ok) return;
  const double n = static_cast<double>(fit.size());
  const detail::SpreadSums spread =
      detail::spread_sums(fit, plane.normal, plane.d, plane.centre, plane.axis1, plane.axis2);
  const double sum_sq = spread.sum_sq, s1 = spread.s1, s2 = spread.s2, h1 = spread.h1,
               h2 = spread.h2;
  const double extent[4] = {spread.min1, spread.max1, spread.min2, spread.max2};
  plane.rms = std::sqrt(sum_sq / n);
  const double dof_scale = fit.size() > 3 ? n / (n - 3) : 0;
  plane.offset_variance = dof_scale * sum_sq / (n * n);
  plane.slope_variance = Eigen::Vector2d(dof_scale * h1 / (s1 * s1), dof_scale * h2 / (s2 * s2));
  plane.slope_variance =
      plane.slope_variance.cwiseMax(jackknife_slope_variance(fit, plane, extent));
}

// Median of `values`: exact up to 16384 values (a marker's own points), above that the median of
// an evenly strided sample of 4096 (about 2 % standard error). It only sets a 3-sigma band, and an
// exact selection over a coplanar wall's ~10^5 points cost more than the fit. The marker's own band
// stays exact: it decides whether the surround is coplanar, a share compared with a threshold.
template <typename Values>
double median_of(const Values& values) {
  constexpr std::size_t kExact = 16384, kSample = 4096;
  if (values.size() <= kExact)
    return detail::value_of_rank(values.data(), values.size(), values.size() / 2);
  thread_local std::vector<double> sample;
  const std::size_t stride = values.size() / kSample;
  sample.clear();
  for (std::size_t k = 0; k < values.size(); k += stride) sample.push_back(values[k]);
  return detail::value_of_rank(sample.data(), sample.size(), sample.size() / 2);
}

std::vector<cv::Point> rounded(const std::vector<Vec2>& polygon_px, cv::Point origin) {
  std::vector<cv::Point> out;
  for (const Vec2& p : polygon_px)
    out.emplace_back(static_cast<int>(std::lround(p.x())) - origin.x,
                     static_cast<int>(std::lround(p.y())) - origin.y);
  return out;
}

// Polygons are drawn in a frame uniform in angle, so a marker keeps its shape and a surround
// scaled about it covers the same angles on every side, also when image rows follow rings.
struct PolygonFrame {
  ImageGeometry uniform;     // uniform rows, the image's columns
  std::vector<double> v_of;  // uniform row coordinate of each image row
};

PolygonFrame polygon_frame(const ImageGeometry& g) {
  PolygonFrame frame;
  frame.uniform = g.ring_rows() ? square_pixel_geometry(g) : g;
  frame.v_of.resize(static_cast<std::size_t>(std::max(g.height, 0)));
  for (int r = 0; r < g.height; ++r)
    frame.v_of[static_cast<std::size_t>(r)] =
        g.ring_rows() ? frame.uniform.v_of_elevation(g.elevation_of_v(r)) : r;
  return frame;
}

// The points of the observed pixels inside nested polygons (in the frame's uniform coordinates),
// gathered in one pass, each labelled with the innermost polygon holding it: label k + 1 for
// `nested[k]`, outermost first. A pixel holding one point contributes that point, one holding
// several its mean range along the pixel-centre ray. Large boxes are split between `threads` by
// rows: the same points in the same order for any count.
struct LabelledPoints {
  detail::FitPoints points;
  detail::Buffer<std::uint8_t> label;
};

void gather_points(const std::vector<std::vector<Vec2>>& nested, const ProjectedImage& image,
                   const PointView& cloud, const PolygonFrame& frame, int threads,
                   LabelledPoints& out) {
  out.points.resize(0);
  out.label.clear();
  const ImageGeometry& g = image.geometry;
  double min_u = 1e18, max_u = -1e18, min_v = 1e18, max_v = -1e18;
  for (const std::vector<Vec2>& polygon : nested) {
    if (polygon.size() < 3) return;
    for (const Vec2& p : polygon) {
      if (!p.allFinite()) return;
      min_u = std::min(min_u, p.x());
      max_u = std::max(max_u, p.x());
      min_v = std::min(min_v, p.y());
      max_v = std::max(max_v, p.y());
    }
  }
  if (nested.empty()) return;
  // A full-circle image continues past its first and last columns (a marker across the seam).
  const int reach = g.full_circle() ? g.width / 2 : 0;
  const int c0 = std::max(-reach, static_cast<int>(std::floor(min_u)));
  const int c1 = std::min(g.width - 1 + reach, static_cast<int>(std::ceil(max_u)));
  const int v0 = static_cast<int>(std::floor(min_v)), v1 = static_cast<int>(std::ceil(max_v));
  if (c0 > c1 || v0 > v1) return;

  // Rasterise the polygons, outermost first, into one label mask over their bounding box.
  thread_local cv::Mat labels;
  labels.create(v1 - v0 + 1, c1 - c0 + 1, CV_8U);
  labels.setTo(cv::Scalar(0));
  for (std::size_t k = 0; k < nested.size(); ++k)
    cv::fillConvexPoly(labels, rounded(nested[k], cv::Point(c0, v0)),
                       cv::Scalar(static_cast<double>(k + 1)));

  // Per column of the box: the image column (-1: none) and its pixel-centre ray components,
  // computed once (ImageGeometry::ray's formula).
  thread_local std::vector<int> column;
  thread_local std::vector<double> cos_az, sin_az;
  column.resize(static_cast<std::size_t>(c1 - c0 + 1));
  cos_az.resize(column.size());
  sin_az.resize(column.size());
  for (int c = c0; c <= c1; ++c) {
    const std::size_t k = static_cast<std::size_t>(c - c0);
    const int wrapped = g.wrap_column(c);
    column[k] = wrapped >= 0 && wrapped < g.width ? wrapped : -1;
    const double azimuth = g.azimuth_of_u(wrapped);
    cos_az[k] = std::cos(azimuth);
    sin_az[k] = std::sin(azimuth);
  }
  // A single-point pixel's slot among the gathered points and its point in the cloud. No member
  // initialisers: the buffer's new elements stay unwritten (a std::pair would zero them).
  struct SinglePoint {
    std::uint32_t slot, point;
  };
  thread_local detail::Buffer<SinglePoint> single;
  thread_local std::vector<int> box_rows;  // the image rows the box spans, top to bottom
  box_rows.clear();
  for (int r = 0; r < g.height; ++r) {
    const int v = static_cast<int>(std::lround(frame.v_of[static_cast<std::size_t>(r)]));
    if (v >= v0 && v <= v1) box_rows.push_back(r);
  }
  // Parts of the box's rows go to threads, each writing its points from the slot its rows begin
  // at (every pixel is written to the next free slot, so a part needs a slot per pixel and one
  // spare); the parts' points are then moved together, in the order of one pass.
  const std::size_t width = column.size();
  const bool inside = c0 >= 0 && c1 < g.width;  // every column of the box is its image column
  constexpr std::size_t kMinPixelsPerPart = 32768;
  const int parts = detail::parts_for(threads, box_rows.size() * width, kMinPixelsPerPart);
  const std::size_t most = box_rows.size() * width + static_cast<std::size_t>(parts);
  detail::FitPoints& fit = out.points;
  fit.resize(most);
  out.label.resize(most);
  single.resize(most);
  // Written through plain pointers (a push_back per point reloaded the thread-local vectors'
  // ends), and through these names alone in the parts: a thread-local named in a helper thread
  // is that thread's own.
  float* const xs = fit.x.data();
  float* const ys = fit.y.data();
  float* const zs = fit.z.data();
  std::uint8_t* const labelled = out.label.data();
  SinglePoint* const singles = single.data();
  const std::vector<int>& rows = box_rows;
  const std::vector<int>& columns = column;
  const std::vector<double>& cos_of = cos_az;
  const std::vector<double>& sin_of = sin_az;
  const cv::Mat& label_mask = labels;
  std::size_t first_slot[detail::kMaxParts], gathered[detail::kMaxParts];
  detail::in_parts(parts, [&](int part, int count) {
    const auto [first, end] = detail::part_range(rows.size(), part, count);
    const std::size_t base = first * width + static_cast<std::size_t>(part);
    float* __restrict x = xs;
    float* __restrict y = ys;
    float* __restrict z = zs;
    std::uint8_t* __restrict l = labelled;
    SinglePoint* __restrict one = singles;
    std::size_t n = base, n_single = base;
    thread_local detail::Buffer<float> ray_x, ray_y, ray_z;  // this thread's, one row's
    for (std::size_t i = first; i < end; ++i) {
      const int r = rows[i];
      const int v = static_cast<int>(std::lround(frame.v_of[static_cast<std::size_t>(r)]));
      const std::uint8_t* in = label_mask.ptr<std::uint8_t>(v - v0);
      const std::uint8_t* seen = image.mask.ptr<std::uint8_t>(r);
      const std::int32_t* count_of = image.count.ptr<std::int32_t>(r);
      const std::int32_t* index = image.index.ptr<std::int32_t>(r);
      const float* range = image.range.ptr<float>(r);
      const double elevation = g.elevation_of_v(r);
      const double cos_el = std::cos(elevation), sin_el = std::sin(elevation);
      // Every pixel is written to the next slot and counted only when labelled and observed, and
      // a pixel of one point also as a single: no branch on the mix of single- and many-point
      // pixels. A box within the image's columns (the common case) reads them directly.
      if (inside) {
        // The points along the rays first (a pass that vectorises), then the compaction.
        ray_x.resize(width);
        ray_y.resize(width);
        ray_z.resize(width);
        detail::ray_points(cos_el, sin_el, cos_of.data(), sin_of.data(), range + c0, width,
                           ray_x.data(), ray_y.data(), ray_z.data());
        const float* __restrict rx = ray_x.data();
        const float* __restrict ry = ray_y.data();
        const float* __restrict rz = ray_z.data();
        const std::uint8_t* __restrict seen_at = seen + c0;
        const std::int32_t* __restrict count_at = count_of + c0;
        const std::int32_t* __restrict index_at = index + c0;
        for (std::size_t k = 0; k < width; ++k) {
          const std::uint8_t label = in[k];
          const bool taken = (label != 0) & (seen_at[k] != 0);
          x[n] = rx[k];
          y[n] = ry[k];
          z[n] = rz[k];
          l[n] = label;
          one[n_single] = {static_cast<std::uint32_t>(n), static_cast<std::uint32_t>(index_at[k])};
          n_single += taken & (count_at[k] == 1);
          n += taken;
        }
        continue;
      }
      for (std::size_t k = 0; k < width; ++k) {
        const std::uint8_t label = in[k];
        const int c = std::max(columns[k], 0);
        const bool taken = (label != 0) & (columns[k] >= 0) & (seen[c] != 0);
        const double along = static_cast<double>(range[c]);
        x[n] = static_cast<float>(cos_el * cos_of[k] * along);
        y[n] = static_cast<float>(cos_el * sin_of[k] * along);
        z[n] = static_cast<float>(sin_el * along);
        l[n] = label;
        one[n_single] = {static_cast<std::uint32_t>(n), static_cast<std::uint32_t>(index[c])};
        n_single += taken & (count_of[c] == 1);
        n += taken;
      }
    }
    // The single-point pixels' points, read from the cloud in a second pass with prefetching: the
    // points of neighbouring pixels lie anywhere in the cloud (a rosette revisits a spot every few
    // frames), and waiting for each miss in turn cost more than the whole fit.
    constexpr std::size_t kAhead = 16;
    for (std::size_t k = base; k < n_single; ++k) {
      if (k + kAhead < n_single) {
        const std::size_t ahead = one[k + kAhead].point;
        __builtin_prefetch(cloud.x.data + static_cast<std::ptrdiff_t>(ahead) * cloud.x.stride);
        __builtin_prefetch(cloud.y.data + static_cast<std::ptrdiff_t>(ahead) * cloud.y.stride);
        __builtin_prefetch(cloud.z.data + static_cast<std::ptrdiff_t>(ahead) * cloud.z.stride);
      }
      const std::size_t point = one[k].point, slot = one[k].slot;
      x[slot] = cloud.x[point];
      y[slot] = cloud.y[point];
      z[slot] = cloud.z[point];
    }
    first_slot[part] = base;
    gathered[part] = n - base;
  });
  std::size_t n = 0;
  for (int part = 0; part < parts; ++part) {
    const std::size_t from = first_slot[part], count = gathered[part];
    if (from != n) {
      std::memmove(xs + n, xs + from, count * sizeof(float));
      std::memmove(ys + n, ys + from, count * sizeof(float));
      std::memmove(zs + n, zs + from, count * sizeof(float));
      std::memmove(labelled + n, labelled + from, count);
    }
    n += count;
  }
  fit.resize(n);
  out.label.resize(n);
}

// Least squares over `fit`, then refits without points farther than max(min band, 3 robust
// sigmas). Leaves the final inliers in `fit`. The uncertainty (add_plane_uncertainty, a good part
// of the cost) only when asked for.
enum class Uncertainty { kWanted, kNotWanted };
Plane robust_plane(detail::FitPoints& fit, const PlaneFitOptions& options, double* band_out,
                   Uncertainty uncertainty = Uncertainty::kWanted) {
  if (fit.size() == 0) return Plane{};
  thread_local detail::FitPoints kept;
  const Vec3 first(fit.x[0], fit.y[0], fit.z[0]);
  Plane plane = plane_from_moments(Moments(detail::coordinate_sums(fit, first), first));
  thread_local detail::Buffer<double> residuals;
  double band = options.min_inlier_band_m;
  for (int it = 0; it < options.iterations && plane.ok; ++it) {
    residuals.resize(fit.size());
    detail::plane_residuals(fit, plane.normal, plane.d, residuals.data());
    band = std::max(options.min_inlier_band_m, 3 * 1.4826 * median_of(residuals));
    const std::size_t n_kept = detail::keep_within(fit, residuals.data(), band, kept);
    if (n_kept < options.min_points || n_kept == fit.size()) break;
    std::swap(fit, kept);
    plane = plane_from_moments(Moments(detail::coordinate_sums(fit, plane.centre), plane.centre));
  }
  if (uncertainty == Uncertainty::kWanted) add_plane_uncertainty(fit, plane);
  if (band_out) *band_out = band;
  return plane;
}

// Whether a ring (labels first_label..last_label, `ring_points` of them) that is off the marker's
// own plane still holds the marker. That plane may be the one at fault: a marker crossed by few
// scan lines (a VLP-16's 17 cm tag at 1 m spans four rings) can fit a plane tilted by many degrees,
// off which its flat wall then seems to lie. So the ring is judged on its own plane. It must be
// planar (the share of its points within its band that the coplanar test asks for), and the marker
// must lie on it: its own plane's tilt from the ring's within its uncertainty (a sheet turned away
// from its wall is not), the same share of its points within the band, and their mean offset within
// 3 standard errors and 3 mm (a sheet standing proud keeps its own plane). When it holds, `offsets`
// holds every point's distance from the ring's plane and `ring_band` that plane's band.
bool ring_holds_the_marker(const detail::FitPoints& points, const std::uint8_t* label,
                           std::uint8_t first_label, std::uint8_t last_label,
                           std::size_t ring_points, std::uint8_t marker_label, const Plane& own,
                           const PlaneFitOptions& options, detail::Buffer<double>& offsets,
                           double& ring_band) {
  // The ring's plane only has to be good enough to judge the marker by, and an evenly strided
  // sample of at most 4096 of its points gives it at a fraction of the cost (a 3x surround on a
  // dense image holds tens of thousands). Its band is a robust sigma, which the sample keeps.
  constexpr std::size_t kMaxRingSample = 4096;
  const std::size_t stride =
      std::max<std::size_t>(1, (ring_points + kMaxRingSample - 1) / kMaxRingSample);
  thread_local detail::FitPoints ring;
  ring.resize(ring_points / stride + 1);
  std::size_t kept = 0, skip = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (label[i] < first_label || label[i] > last_label) continue;
    if (skip > 0) {
      --skip;
      continue;
    }
    skip = stride - 1;
    ring.x[kept] = points.x[i];
    ring.y[kept] = points.y[i];
    ring.z[kept] = points.z[i];
    ++kept;
  }
  ring.resize(kept);
  double band = 0;
  const Plane wall = robust_plane(ring, options, &band, Uncertainty::kNotWanted);
  if (!wall.ok) return false;
  // The marker's own tilt from the ring's plane, in its own slopes' uncertainty (chi-square, two
  // degrees of freedom). Chance draws on four rings reach 16-26 (the VLP-16 sweep, the tests); a
  // sheet turned 10 degrees from its wall, seen with 5 mm noise, gives 355.
  constexpr double kMaxTiltChiSquare = 30;
  const double along = std::abs(wall.normal.dot(own.normal));
  const double slope1 = wall.normal.dot(own.axis1) / along;
  const double slope2 = wall.normal.dot(own.axis2) / along;
  const double tilt_chi_square =
      slope1 * slope1 / own.slope_variance(0) + slope2 * slope2 / own.slope_variance(1);
  if (!(tilt_chi_square <= kMaxTiltChiSquare)) return false;
  offsets.resize(points.size());
  detail::plane_residuals(points, wall.normal, wall.d, offsets.data());
  std::size_t ring_close = 0, marker_points = 0, marker_close = 0;
  double sum = 0, sum_sq = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool close = offsets[i] <= band;
    if (label[i] == marker_label) {
      const double offset = wall.normal.dot(Vec3(points.x[i], points.y[i], points.z[i])) - wall.d;
      sum += offset;
      sum_sq += offset * offset;
      ++marker_points;
      marker_close += close;
    } else if (label[i] >= first_label && label[i] <= last_label) {
      ring_close += close;
    }
  }
  const auto share_close = [&](std::size_t close, std::size_t of) {
    return static_cast<double>(close) >= options.min_coplanar_fraction * static_cast<double>(of);
  };
  if (marker_points < 2 || !share_close(ring_close, ring_points) ||
      !share_close(marker_close, marker_points))
    return false;
  const double n = static_cast<double>(marker_points), mean = sum / n;
  const double variance = std::max(0.0, (sum_sq - n * mean * mean) / (n - 1));
  constexpr double kFlushSlackM = 0.003;
  if (std::abs(mean) > 3 * std::sqrt(variance / n) + kFlushSlackM) return false;
  ring_band = band;
  return true;
}

std::vector<Vec2> scaled_about_centre(const std::vector<Vec2>& polygon, double scale) {
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : polygon) centre += p / static_cast<double>(polygon.size());
  std::vector<Vec2> out;
  for (const Vec2& p : polygon) out.push_back(centre + scale * (p - centre));
  return out;
}

}  // namespace

Plane fit_marker_plane(const std::vector<Vec2>& polygon_px, const ProjectedImage& image,
                       const PointView& cloud, const PlaneFitOptions& options) {
  const PolygonFrame frame = polygon_frame(image.geometry);
  std::vector<Vec2> polygon;
  for (const Vec2& px : polygon_px) polygon.push_back(map_pixel(px, image.geometry, frame.uniform));

  // Surrounds largest first, then the marker: the marker's points get the last label.
  std::vector<double> scales;
  for (double s : options.surround_scales)
    if (s > 1) scales.push_back(s);
  std::sort(scales.begin(), scales.end(), std::greater<double>());
  std::vector<std::vector<Vec2>> nested;
  for (double s : scales) nested.push_back(scaled_about_centre(polygon, s));
  nested.push_back(polygon);
  const std::uint8_t marker_label = static_cast<std::uint8_t>(nested.size());
  thread_local LabelledPoints gathered;
  gather_points(nested, image, cloud, frame, options.threads, gathered);
  const detail::FitPoints& points = gathered.points;
  const std::uint8_t* label = gathered.label.data();

  // The marker's points, then (robust_plane) its inliers.
  thread_local detail::FitPoints marker, all;
  detail::keep_labelled(points, label, marker_label, marker_label, marker);
  if (marker.size() < options.min_points) return Plane{};
  double band = 0;
  Plane plane = robust_plane(marker, options, &band, Uncertainty::kNotWanted);
  if (!plane.ok) return plane;
  // Its uncertainty (the jackknife's sums over its points) only where it is used: a plane
  // returned without a surround, and a surround off it judged against its tilt.
  bool with_uncertainty = false;
  const auto own_plane = [&]() -> const Plane& {
    if (!with_uncertainty) add_plane_uncertainty(marker, plane);
    with_uncertainty = true;
    return plane;
  };

  // A printed sheet is flush with what it hangs on: when the surround is coplanar with the marker,
  // its points pin the normal down far better (more points, longer lever). Largest ring first;
  // surround k's ring holds the labels k + 1 up to the marker's, exclusive.
  thread_local detail::Buffer<double> offsets_all, offsets_from_ring, offsets;
  offsets_all.resize(points.size());
  detail::plane_residuals(points, plane.normal, plane.d, offsets_all.data());
  for (std::size_t k = 0; k < scales.size(); ++k) {
    const auto first_label = static_cast<std::uint8_t>(k + 1);
    const auto last_label = static_cast<std::uint8_t>(marker_label - 1);
    // The ring's offsets, compacted without a branch (every offset written, kept when in it).
    offsets.resize(points.size());
    std::size_t coplanar = 0, in_ring = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const bool in = (label[i] >= first_label) & (label[i] <= last_label);
      offsets[in_ring] = offsets_all[i];
      coplanar += in & (offsets_all[i] <= band);
      in_ring += in;
    }
    offsets.resize(in_ring);
    if (offsets.size() < marker.size() / 2) continue;
    // The ring's points within `ring_band` of the marker's plane (coplanar) or of the ring's own
    // (ring_holds_the_marker) join the marker's for the wide fit.
    const double* ring_offsets = offsets_all.data();
    double ring_band = 0;
    if (coplanar >= options.min_coplanar_fraction * static_cast<double>(offsets.size())) {
      // Coplanar: take the ring's points within 4 of its own robust sigmas. The marker's band is
      // too narrow for the ring when the ring's pixels average fewer returns (a rosette is densest
      // at its centre): cutting the ring's tails about the marker's own, tilted plane pulls the
      // wide fit towards the marker's tilt (measured: twice the tilt error of an untruncated fit).
      ring_band = std::max(band, 4 * 1.4826 * median_of(offsets));
    } else if (ring_holds_the_marker(points, label, first_label, last_label, offsets.size(),
                                     marker_label, own_plane(), options, offsets_from_ring,
                                     ring_band)) {
      ring_offsets = offsets_from_ring.data();
    } else {
      continue;
    }
    all = marker;
    detail::append_labelled_within(points, label, first_label, last_label, ring_offsets, ring_band,
                                   all);
    Plane wide = robust_plane(all, options, nullptr);
    if (!wide.ok) continue;
    // The normal from the wide fit; the offset from the marker's own points, so a sheet standing a
    // little proud of its wall (a board, a thick print) keeps its own depth.
    double offset = 0;
    Vec3 centre = Vec3::Zero();
    for (std::size_t i = 0; i < marker.size(); ++i) {
      const Vec3 p(marker.x[i], marker.y[i], marker.z[i]);
      offset += wide.normal.dot(p);
      centre += p;
    }
    const double n_marker = static_cast<double>(marker.size());
    wide.d = offset / n_marker;
    wide.surround_scale = scales[k];
    // The offset is the marker points' mean (the variance of a mean of their residuals), the
    // slopes the wide fit's, about the marker's centroid.
    double sum_sq = 0;
    for (std::size_t i = 0; i < marker.size(); ++i)
      sum_sq += std::pow(wide.normal.dot(Vec3(marker.x[i], marker.y[i], marker.z[i])) - wide.d, 2);
    wide.offset_variance = sum_sq / (n_marker * std::max(1.0, n_marker - 1));
    wide.centre = centre / n_marker;
    return wide;
  }
  return own_plane();
}

LiftedCorner lift_on_plane(const Vec2& keypoint_px, const ProjectedImage& image,
                           const Plane& plane) {
  LiftedCorner lifted;
  if (!plane.ok || !keypoint_px.allFinite()) return lifted;
  const Vec3 ray = image.geometry.ray(keypoint_px);
  const double along = plane.normal.dot(ray);
  // Grazing rays (under ~3 deg to the plane) put the corner anywhere along the plane.
  if (std::abs(along) < 0.05) return lifted;
  const double t = plane.d / along;
  if (!(t > 0)) return lifted;
  lifted.point = ray * t;
  const int col = image.geometry.wrap_column(static_cast<int>(std::lround(keypoint_px.x())));
  const int row = static_cast<int>(std::lround(keypoint_px.y()));
  const bool observed = image.geometry.contains_pixel(col, row) && image.observed(col, row);
  lifted.status = observed ? CornerStatus::kObserved : CornerStatus::kInterpolated;
  return lifted;
}

}  // namespace iilfm
