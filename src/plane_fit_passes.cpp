#include "plane_fit_passes.hpp"

#include <algorithm>
#include <cmath>

#include "cpu_clones.hpp"

namespace iilfm::detail {

namespace {

constexpr std::size_t kLanes = 4;

// Four doubles as one value (GCC's vector extension: one AVX2 register, two SSE2 ones), lane j
// fed from every fourth point. Written with lane arrays, GCC left most of these sums scalar.
// Unaligned and allowed to alias doubles, so the residuals are read through it (the points,
// floats, through FloatLanes).
using Lanes = double __attribute__((vector_size(kLanes * sizeof(double)), aligned(8), may_alias));

// The helpers take and give Lanes through references: a Lanes value passed between functions
// built for different instruction sets (an AVX2 clone and a baseline helper) travels in
// different registers, and a debug build does not inline the helpers (GCC's -Wpsabi).
void load(const double* p, Lanes& out) { out = *reinterpret_cast<const Lanes*>(p); }

// Four floats widened to four doubles.
using FloatLanes =
    float __attribute__((vector_size(kLanes * sizeof(float)), aligned(4), may_alias));
void load(const float* p, Lanes& out) {
  out = __builtin_convertvector(*reinterpret_cast<const FloatLanes*>(p), Lanes);
}

// Lane sums added in one order: the same total for any vector width.
double total(const Lanes& lanes) { return ((lanes[0] + lanes[1]) + lanes[2]) + lanes[3]; }

IILFM_AVX2_CLONES void sums_of(const float* __restrict x, const float* __restrict y,
                               const float* __restrict z, std::size_t n, double rx, double ry,
                               double rz, CoordinateSums& out) {
  Lanes sx{}, sy{}, sz{}, sxx{}, sxy{}, sxz{}, syy{}, syz{}, szz{};
  const std::size_t whole = n - n % kLanes;
  for (std::size_t k = 0; k < whole; k += kLanes) {
    Lanes a, b, c;
    load(x + k, a);
    load(y + k, b);
    load(z + k, c);
    a -= rx;
    b -= ry;
    c -= rz;
    sx += a;
    sy += b;
    sz += c;
    sxx += a * a;
    sxy += a * b;
    sxz += a * c;
    syy += b * b;
    syz += b * c;
    szz += c * c;
  }
  for (std::size_t k = whole; k < n; ++k) {  // the rest into lane 0
    const double a = x[k] - rx, b = y[k] - ry, c = z[k] - rz;
    sx[0] += a;
    sy[0] += b;
    sz[0] += c;
    sxx[0] += a * a;
    sxy[0] += a * b;
    sxz[0] += a * c;
    syy[0] += b * b;
    syz[0] += b * c;
    szz[0] += c * c;
  }
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

IILFM_AVX2_CLONES void residuals_of(const float* __restrict x, const float* __restrict y,
                                    const float* __restrict z, std::size_t n, double nx, double ny,
                                    double nz, double d, double* __restrict out) {
  for (std::size_t k = 0; k < n; ++k) out[k] = std::abs(nx * x[k] + ny * y[k] + nz * z[k] - d);
}

// Lane-wise minimum and maximum; a NaN never wins.
void take_range(const Lanes& v, Lanes& lo, Lanes& hi) {
  lo = v < lo ? v : lo;
  hi = v > hi ? v : hi;
}
double lowest(const Lanes& v) { return std::min({v[0], v[1], v[2], v[3]}); }
double highest(const Lanes& v) { return std::max({v[0], v[1], v[2], v[3]}); }

IILFM_AVX2_CLONES void spread_of(const float* __restrict x, const float* __restrict y,
                                 const float* __restrict z, std::size_t n, const double* plane,
                                 SpreadSums& out) {
  const double nx = plane[0], ny = plane[1], nz = plane[2], d = plane[3];
  const double cx = plane[4], cy = plane[5], cz = plane[6];
  const double ax = plane[7], ay = plane[8], az = plane[9];
  const double bx = plane[10], by = plane[11], bz = plane[12];
  Lanes sq{}, s1{}, s2{}, h1{}, h2{};
  Lanes lo1 = Lanes{} + 1e300, hi1 = Lanes{} - 1e300, lo2 = lo1, hi2 = hi1;
  // A point's squared residual and in-plane coordinates, for lanes of points or for one point
  // (through references, as the helpers above).
  const auto terms = [&](const auto& px, const auto& py, const auto& pz, auto& r2, auto& x1,
                         auto& x2) {
    const auto r = nx * px + ny * py + nz * pz - d;
    const auto qx = px - cx, qy = py - cy, qz = pz - cz;
    r2 = r * r;
    x1 = qx * ax + qy * ay + qz * az;
    x2 = qx * bx + qy * by + qz * bz;
  };
  const std::size_t whole = n - n % kLanes;
  for (std::size_t k = 0; k < whole; k += kLanes) {
    Lanes px, py, pz, r2, x1, x2;
    load(x + k, px);
    load(y + k, py);
    load(z + k, pz);
    terms(px, py, pz, r2, x1, x2);
    sq += r2;
    s1 += x1 * x1;
    s2 += x2 * x2;
    h1 += x1 * x1 * r2;
    h2 += x2 * x2 * r2;
    take_range(x1, lo1, hi1);
    take_range(x2, lo2, hi2);
  }
  for (std::size_t k = whole; k < n; ++k) {  // the rest into lane 0
    double r2, x1, x2;
    terms(x[k], y[k], z[k], r2, x1, x2);
    sq[0] += r2;
    s1[0] += x1 * x1;
    s2[0] += x2 * x2;
    h1[0] += x1 * x1 * r2;
    h2[0] += x2 * x2 * r2;
    lo1[0] = x1 < lo1[0] ? x1 : lo1[0];
    hi1[0] = x1 > hi1[0] ? x1 : hi1[0];
    lo2[0] = x2 < lo2[0] ? x2 : lo2[0];
    hi2[0] = x2 > hi2[0] ? x2 : hi2[0];
  }
  out.sum_sq = total(sq);
  out.s1 = total(s1);
  out.s2 = total(s2);
  out.h1 = total(h1);
  out.h2 = total(h2);
  out.min1 = lowest(lo1);
  out.max1 = highest(hi1);
  out.min2 = lowest(lo2);
  out.max2 = highest(hi2);
}

IILFM_AVX2_CLONES void patches_of(const float* __restrict x, const float* __restrict y,
                                  const float* __restrict z, std::size_t n, const double* frame,
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
  Lanes lo = Lanes{} + v[0], hi = lo;
  const std::size_t whole = n - n % kLanes;
  for (std::size_t k = 0; k < whole; k += kLanes) {
    Lanes values;
    load(v + k, values);
    take_range(values, lo, hi);
  }
  for (std::size_t k = whole; k < n; ++k) {
    lo[0] = v[k] < lo[0] ? v[k] : lo[0];
    hi[0] = v[k] > hi[0] ? v[k] : hi[0];
  }
  lo_out = lowest(lo);
  hi_out = highest(hi);
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
  // than every value of a higher one. Clamped before the conversion (NaN gives bin 0).
  const auto bin = [&](double value) {
    return static_cast<std::int32_t>(
        std::min(static_cast<double>(kBins - 1), std::max(0.0, (value - lo) * scale)));
  };
  thread_local Buffer<std::int32_t> bins;
  bins.resize(n);
  std::int32_t* __restrict bin_of = bins.data();
  for (std::size_t k = 0; k < n; ++k) bin_of[k] = bin(v[k]);  // vectorises
  // Four histograms taken in turn: residuals cluster in a few bins, and one histogram made each
  // count wait for the store of the one before.
  std::uint32_t count[4][kBins] = {};
  const std::size_t whole = n - n % 4;
  for (std::size_t k = 0; k < whole; k += 4)
    for (std::size_t j = 0; j < 4; ++j) ++count[j][bin_of[k + j]];
  for (std::size_t k = whole; k < n; ++k) ++count[0][bin_of[k]];
  const auto in_bin = [&](std::size_t b) {
    return std::size_t{count[0][b]} + count[1][b] + count[2][b] + count[3][b];
  };
  std::size_t b = 0, below = 0;
  while (below + in_bin(b) <= rank) below += in_bin(b++);
  chosen.clear();
  const auto chosen_bin = static_cast<std::int32_t>(b);
  for (std::size_t k = 0; k < n; ++k)
    if (bin_of[k] == chosen_bin) chosen.push_back(v[k]);
  return select(rank - below);
}

namespace {

// Appends from[k] for k in [begin, end) to `to` (sized for all of them past `kept`) where take(k),
// in order; returns the new count. Every point is written, and counted when taken: no branch to
// mispredict on a noisy band edge or a ragged label boundary.
template <typename Take>
std::size_t compact(const FitPoints& from, std::size_t begin, std::size_t end, std::size_t kept,
                    FitPoints& to, Take&& take) {
  for (std::size_t k = begin; k < end; ++k) {
    to.x[kept] = from.x[k];
    to.y[kept] = from.y[k];
    to.z[kept] = from.z[k];
    kept += take(k) ? 1 : 0;
  }
  return kept;
}

}  // namespace

void keep_labelled(const FitPoints& from, const std::uint8_t* label, std::uint8_t lo,
                   std::uint8_t hi, FitPoints& to) {
  to.resize(from.size());
  to.resize(compact(from, 0, from.size(), 0, to,
                    [&](std::size_t k) { return label[k] >= lo && label[k] <= hi; }));
}

void append_labelled_within(const FitPoints& from, const std::uint8_t* label, std::uint8_t lo,
                            std::uint8_t hi, const double* value, double band, FitPoints& to) {
  const std::size_t before = to.size();
  to.resize(before + from.size());
  to.resize(compact(from, 0, from.size(), before, to, [&](std::size_t k) {
    return (label[k] >= lo) & (label[k] <= hi) & (value[k] <= band);
  }));
}

CoordinateSums coordinate_sums(const FitPoints& p, const Vec3& ref) {
  return coordinate_sums(p, ref, 0, p.size());
}

CoordinateSums coordinate_sums(const FitPoints& p, const Vec3& ref, std::size_t begin,
                               std::size_t end) {
  CoordinateSums sums;
  sums_of(p.x.data() + begin, p.y.data() + begin, p.z.data() + begin, end - begin, ref.x(), ref.y(),
          ref.z(), sums);
  return sums;
}

IILFM_AVX2_CLONES void ray_points(double cos_el, double sin_el, const double* __restrict cos_az,
                                  const double* __restrict sin_az, const float* __restrict range,
                                  std::size_t n, float* __restrict x, float* __restrict y,
                                  float* __restrict z) {
  for (std::size_t k = 0; k < n; ++k) {
    const double along = static_cast<double>(range[k]);
    x[k] = static_cast<float>(cos_el * cos_az[k] * along);
    y[k] = static_cast<float>(cos_el * sin_az[k] * along);
    z[k] = static_cast<float>(sin_el * along);
  }
}

void plane_residuals(const FitPoints& p, const Vec3& normal, double d, double* residual) {
  residuals_of(p.x.data(), p.y.data(), p.z.data(), p.size(), normal.x(), normal.y(), normal.z(), d,
               residual);
}

std::size_t keep_within(const FitPoints& from, const double* residual, double band, FitPoints& to) {
  const std::size_t n = from.size();
  to.resize(n);
  std::size_t kept = 0;
  // Most points are kept: a block of them all within the band is copied whole.
  constexpr std::size_t kBlock = 64;
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t end = std::min(n, start + kBlock);
    std::size_t outside = 0;
    for (std::size_t k = start; k < end; ++k) outside += !(residual[k] <= band);
    if (outside == 0) {
      std::copy(from.x.data() + start, from.x.data() + end, to.x.data() + kept);
      std::copy(from.y.data() + start, from.y.data() + end, to.y.data() + kept);
      std::copy(from.z.data() + start, from.z.data() + end, to.z.data() + kept);
      kept += end - start;
      continue;
    }
    kept = compact(from, start, end, kept, to, [&](std::size_t k) { return residual[k] <= band; });
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
