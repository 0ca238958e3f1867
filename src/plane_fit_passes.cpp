#include "plane_fit_passes.hpp"

#include <algorithm>
#include <cmath>

#include "cpu_clones.hpp"
#include "lane_range.hpp"

namespace iilfm::detail {

namespace {

constexpr std::size_t kLanes = 4;

// Lane sums added in one order: the same total for any vector width.
double total(const double (&lanes)[kLanes]) {
  return ((lanes[0] + lanes[1]) + lanes[2]) + lanes[3];
}

IILFM_AVX2_CLONES void sums_of(const double* __restrict x, const double* __restrict y,
                               const double* __restrict z, std::size_t n, double rx, double ry,
                               double rz, CoordinateSums& out) {
  double sx[kLanes] = {}, sy[kLanes] = {}, sz[kLanes] = {}, sxx[kLanes] = {}, sxy[kLanes] = {},
         sxz[kLanes] = {}, syy[kLanes] = {}, syz[kLanes] = {}, szz[kLanes] = {};
  const auto add = [&](std::size_t k, std::size_t j) {
    const double a = x[k] - rx, b = y[k] - ry, c = z[k] - rz;
    sx[j] += a;
    sy[j] += b;
    sz[j] += c;
    sxx[j] += a * a;
    sxy[j] += a * b;
    sxz[j] += a * c;
    syy[j] += b * b;
    syz[j] += b * c;
    szz[j] += c * c;
  };
  const std::size_t whole = n - n % kLanes;
  for (std::size_t k = 0; k < whole; k += kLanes)
    for (std::size_t j = 0; j < kLanes; ++j) add(k + j, j);
  for (std::size_t k = whole; k < n; ++k) add(k, 0);
  out.n = static_cast<double>(n);
  out.x = total(sx);
  out.y = total(sy);
  out.z = total(sz);
  out.xx = total(sxx);
  out.xy = total(sxy);
  out.xz = total(sxz);
  out.yy = total(syy);
  out.yz = total(syz);
  out.zz = total(szz);
}

IILFM_AVX2_CLONES void residuals_of(const double* __restrict x, const double* __restrict y,
                                    const double* __restrict z, std::size_t n, double nx, double ny,
                                    double nz, double d, double* __restrict out) {
  for (std::size_t k = 0; k < n; ++k) out[k] = std::abs(nx * x[k] + ny * y[k] + nz * z[k] - d);
}

IILFM_AVX2_CLONES void spread_of(const double* __restrict x, const double* __restrict y,
                                 const double* __restrict z, std::size_t n, const double* plane,
                                 SpreadSums& out) {
  const double nx = plane[0], ny = plane[1], nz = plane[2], d = plane[3];
  const double cx = plane[4], cy = plane[5], cz = plane[6];
  const double ax = plane[7], ay = plane[8], az = plane[9];
  const double bx = plane[10], by = plane[11], bz = plane[12];
  double sq[kLanes] = {}, s1[kLanes] = {}, s2[kLanes] = {}, h1[kLanes] = {}, h2[kLanes] = {};
  LaneRange<double, kLanes> along1(1e300, -1e300), along2(1e300, -1e300);
  const auto add = [&](std::size_t k, std::size_t j) {
    const double r = nx * x[k] + ny * y[k] + nz * z[k] - d;
    const double r2 = r * r;
    const double qx = x[k] - cx, qy = y[k] - cy, qz = z[k] - cz;
    const double x1 = qx * ax + qy * ay + qz * az, x2 = qx * bx + qy * by + qz * bz;
    sq[j] += r2;
    s1[j] += x1 * x1;
    s2[j] += x2 * x2;
    h1[j] += x1 * x1 * r2;
    h2[j] += x2 * x2 * r2;
    along1.add(j, x1);
    along2.add(j, x2);
  };
  const std::size_t whole = n - n % kLanes;
  for (std::size_t k = 0; k < whole; k += kLanes)
    for (std::size_t j = 0; j < kLanes; ++j) add(k + j, j);
  for (std::size_t k = whole; k < n; ++k) add(k, 0);
  out.sum_sq = total(sq);
  out.s1 = total(s1);
  out.s2 = total(s2);
  out.h1 = total(h1);
  out.h2 = total(h2);
  out.min1 = along1.min();
  out.max1 = along1.max();
  out.min2 = along2.min();
  out.max2 = along2.max();
}

IILFM_AVX2_CLONES void patches_of(const double* __restrict x, const double* __restrict y,
                                  const double* __restrict z, std::size_t n, const double* frame,
                                  int grid, std::int32_t* __restrict patch) {
  const double cx = frame[0], cy = frame[1], cz = frame[2];
  const double ax = frame[3], ay = frame[4], az = frame[5];
  const double bx = frame[6], by = frame[7], bz = frame[8];
  const double from1 = frame[9], scale1 = frame[10], from2 = frame[11], scale2 = frame[12];
  const double last = grid - 1;
  for (std::size_t k = 0; k < n; ++k) {
    const double qx = x[k] - cx, qy = y[k] - cy, qz = z[k] - cz;
    const double u = (qx * ax + qy * ay + qz * az - from1) * scale1;
    const double v = (qx * bx + qy * by + qz * bz - from2) * scale2;
    // Clamped before the conversion (NaN gives 0), then truncated as the cell it lies in.
    const auto b1 = static_cast<std::int32_t>(std::min(last, std::max(0.0, u)));
    const auto b2 = static_cast<std::int32_t>(std::min(last, std::max(0.0, v)));
    patch[k] = b1 * grid + b2;
  }
}

IILFM_AVX2_CLONES void range_of(const double* __restrict v, std::size_t n, double& lo_out,
                                double& hi_out) {
  LaneRange<double, kLanes> range(v[0], v[0]);
  const std::size_t whole = n - n % kLanes;
  for (std::size_t k = 0; k < whole; k += kLanes)
    for (std::size_t j = 0; j < kLanes; ++j) range.add(j, v[k + j]);
  for (std::size_t k = whole; k < n; ++k) range.add(0, v[k]);
  lo_out = range.min();
  hi_out = range.max();
}

}  // namespace

double value_of_rank(const double* v, std::size_t n, std::size_t rank) {
  constexpr std::size_t kDirect = 1024, kBins = 1024;
  thread_local std::vector<double> chosen;
  const auto select = [&](std::size_t k) {
    std::nth_element(chosen.begin(), chosen.begin() + static_cast<std::ptrdiff_t>(k), chosen.end());
    return chosen[k];
  };
  if (n <= kDirect) {
    chosen.assign(v, v + n);
    return select(rank);
  }
  double lo = 0, hi = 0;
  range_of(v, n, lo, hi);
  const double scale = static_cast<double>(kBins) / (hi - lo);
  if (!(hi > lo) || !std::isfinite(scale)) {  // all equal, or a range too small to split
    chosen.assign(v, v + n);
    return select(rank);
  }
  // bin(value) never decreases as the value grows, so every value of a lower bin is smaller
  // than every value of a higher one.
  const auto bin = [&](double value) {
    return std::min(kBins - 1, static_cast<std::size_t>(std::max(0.0, (value - lo) * scale)));
  };
  std::size_t count[kBins] = {};
  for (std::size_t k = 0; k < n; ++k) ++count[bin(v[k])];
  std::size_t b = 0, below = 0;
  while (below + count[b] <= rank) below += count[b++];
  chosen.clear();
  for (std::size_t k = 0; k < n; ++k)
    if (bin(v[k]) == b) chosen.push_back(v[k]);
  return select(rank - below);
}

void load_fit_points(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& used,
                     FitPoints& out) {
  out.resize(used.size());
  for (std::size_t k = 0; k < used.size(); ++k) {
    const Vec3& p = points[used[k]];
    out.x[k] = p.x();
    out.y[k] = p.y();
    out.z[k] = p.z();
    out.index[k] = used[k];
  }
}

CoordinateSums coordinate_sums(const FitPoints& p, const Vec3& ref) {
  CoordinateSums sums;
  sums_of(p.x.data(), p.y.data(), p.z.data(), p.size(), ref.x(), ref.y(), ref.z(), sums);
  return sums;
}

void plane_residuals(const FitPoints& p, const Vec3& normal, double d, double* residual) {
  residuals_of(p.x.data(), p.y.data(), p.z.data(), p.size(), normal.x(), normal.y(), normal.z(), d,
               residual);
}

std::size_t keep_within(const FitPoints& from, const double* residual, double band, FitPoints& to) {
  to.resize(from.size());
  std::size_t kept = 0;
  for (std::size_t k = 0; k < from.size(); ++k) {
    // Written always, counted when kept: no branch to mispredict on a noisy band edge.
    to.x[kept] = from.x[k];
    to.y[kept] = from.y[k];
    to.z[kept] = from.z[k];
    to.index[kept] = from.index[k];
    kept += residual[k] <= band ? 1 : 0;
  }
  to.resize(kept);
  return kept;
}

SpreadSums spread_sums(const FitPoints& p, const Vec3& normal, double d, const Vec3& centre,
                       const Vec3& axis1, const Vec3& axis2) {
  const double plane[13] = {normal.x(), normal.y(), normal.z(), d,         centre.x(),
                            centre.y(), centre.z(), axis1.x(),  axis1.y(), axis1.z(),
                            axis2.x(),  axis2.y(),  axis2.z()};
  SpreadSums sums;
  spread_of(p.x.data(), p.y.data(), p.z.data(), p.size(), plane, sums);
  return sums;
}

void grid_patches(const FitPoints& p, const Vec3& centre, const Vec3& axis1, const Vec3& axis2,
                  const double extent[4], int grid, std::int32_t* patch) {
  const double frame[13] = {centre.x(),
                            centre.y(),
                            centre.z(),
                            axis1.x(),
                            axis1.y(),
                            axis1.z(),
                            axis2.x(),
                            axis2.y(),
                            axis2.z(),
                            extent[0],
                            grid / std::max(extent[1] - extent[0], 1e-9),
                            extent[2],
                            grid / std::max(extent[3] - extent[2], 1e-9)};
  patches_of(p.x.data(), p.y.data(), p.z.data(), p.size(), frame, grid, patch);
}

}  // namespace iilfm::detail
