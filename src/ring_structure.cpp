#include "iilfm/ring_structure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace iilfm {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr std::size_t kMinRings = 4;
constexpr std::size_t kMaxRings = 512;

// Every `stride`-th point is sampled, with a stride that shares no factor with the channel count
// (nor with 2, 3, 5 and 7, for clouds whose count is unknown): drivers write every ring of a column
// before the next column, and a stride of 2 through a 128-channel sweep would see only the even
// rings.
std::size_t sample_stride(std::size_t n, std::size_t max_samples, std::size_t channels) {
  std::size_t stride = (n + max_samples - 1) / max_samples;
  if (stride <= 1) return 1;
  while (std::gcd(stride, 210 * channels) != 1) ++stride;
  return stride;
}

// Enough points to see every ring of a 128-channel sensor many times over, few enough that the
// check costs a fraction of the projection. The ring field's statistics need fewer than the
// elevation histogram (each point says which ring it is).
constexpr std::size_t kMaxElevationSamples = 200'000;
constexpr std::size_t kMaxRingFieldSamples = 32'768;

// Half-width of the band around a ring's elevation that its points must fall in: a quarter of the
// gap to the nearer neighbour, so a point is never closer to the wrong ring.
std::vector<double> ring_bands(const std::vector<double>& elevation) {
  std::vector<double> band(elevation.size());
  for (std::size_t r = 0; r < elevation.size(); ++r) {
    double gap = M_PI;
    if (r > 0) gap = std::min(gap, elevation[r - 1] - elevation[r]);
    if (r + 1 < elevation.size()) gap = std::min(gap, elevation[r] - elevation[r + 1]);
    band[r] = std::max(0.25 * gap, 0.02 * kDeg);
  }
  return band;
}

// Per ring id, from every `stride`-th point: the mean elevation over the points within 0.5 deg of
// the first mean (drops stray returns), how many points that used (`near`), and the finite
// elevations' count and extremes. Counts are integers (a double count added 1 at a time was a
// 4-cycle chain per point), sums per ring in point order.
struct RingMeans {
  std::vector<double> mean;
  std::vector<std::uint32_t> near, finite;
  std::vector<float> lo, hi;
  std::size_t stride = 0;
};

void ring_means(const PointView& cloud, const float* elevation, std::size_t stride,
                RingMeans& out) {
  const std::size_t n = cloud.size(), ring_ids = out.mean.size();
  const StridedColumn<std::uint16_t> ring = cloud.ring;
  out.stride = stride;
  std::vector<double> sum(ring_ids, 0);
  out.finite.assign(ring_ids, 0);
  out.lo.assign(ring_ids, std::numeric_limits<float>::infinity());
  out.hi.assign(ring_ids, -std::numeric_limits<float>::infinity());
  double* const sums = sum.data();
  std::uint32_t* const counts = out.finite.data();
  float* const lo = out.lo.data();
  float* const hi = out.hi.data();
  for (std::size_t i = 0; i < n; i += stride) {
    const float e = elevation[i];
    if (!std::isfinite(e)) continue;
    const std::uint16_t r = ring[i];
    sums[r] += e;
    counts[r] += 1;
    lo[r] = std::min(lo[r], e);
    hi[r] = std::max(hi[r], e);
  }
  std::vector<double>& mean = out.mean;
  bool all_near = true;  // every point within 0.5 deg: the second mean is the first, exactly
  for (std::size_t r = 0; r < ring_ids; ++r) {
    mean[r] = counts[r] > 0 ? sum[r] / counts[r] : 0;
    // |e - mean| grows towards the extremes (rounding keeps the order): they decide for all.
    all_near &= counts[r] == 0 || (std::fabs(lo[r] - mean[r]) <= 0.5 * kDeg &&
                                   std::fabs(hi[r] - mean[r]) <= 0.5 * kDeg);
  }
  if (all_near) {
    out.near = out.finite;
    return;
  }
  std::fill(sum.begin(), sum.end(), 0);
  out.near.assign(ring_ids, 0);
  const double* const means = mean.data();
  std::uint32_t* const nears = out.near.data();
  for (std::size_t i = 0; i < n; i += stride) {
    const std::uint16_t r = ring[i];
    if (!(std::fabs(elevation[i] - means[r]) <= 0.5 * kDeg)) continue;  // NaN too
    sums[r] += elevation[i];
    nears[r] += 1;
  }
  for (std::size_t r = 0; r < ring_ids; ++r)
    if (nears[r] > 0) mean[r] = sum[r] / nears[r];
}

// How many of every `stride`-th point with a finite elevation there are, and how many lie within
// its ring's band. From the rings' extremes when they were taken at that stride and each lies in
// its band (then so does every point between); otherwise point by point.
std::pair<std::size_t, std::size_t> inside_and_total(const PointView& cloud, const float* elevation,
                                                     std::size_t stride, const RingStructure& rings,
                                                     const std::vector<double>& band,
                                                     const RingMeans& means) {
  const std::int32_t* const row_of_ring = rings.row_of_ring.data();
  const double* const ring_elevation = rings.elevation.data();
  const auto in_band = [&](float e, std::int32_t row) {
    return std::fabs(e - ring_elevation[row]) <= band[static_cast<std::size_t>(row)];
  };
  std::size_t inside = 0, total = 0;
  bool extremes_decide = means.stride == stride;
  for (std::size_t r = 0; r < means.finite.size() && extremes_decide; ++r) {
    const std::int32_t row = row_of_ring[r];
    total += means.finite[r];
    if (row < 0 || means.finite[r] == 0) continue;  // a ring without a row: all outside
    extremes_decide = in_band(means.lo[r], row) && in_band(means.hi[r], row);
    inside += means.finite[r];
  }
  if (extremes_decide) return {inside, total};
  inside = total = 0;
  for (std::size_t i = 0; i < cloud.size(); i += stride) {
    if (!std::isfinite(elevation[i])) continue;
    total += 1;
    const std::int32_t row = row_of_ring[cloud.ring[i]];
    inside += row >= 0 && in_band(elevation[i], row) ? 1 : 0;
  }
  return {inside, total};
}

}  // namespace

double RingStructure::mean_spacing() const {
  if (elevation.size() < 2) return 0;
  return (elevation.front() - elevation.back()) / static_cast<double>(elevation.size() - 1);
}

std::optional<RingStructure> rings_from_field(const PointView& cloud, const float* elevation) {
  if (!cloud.has_ring() || cloud.empty()) return std::nullopt;
  const std::size_t n = cloud.size();
  std::uint16_t max_ring = 0;
  for (std::size_t i = 0; i < n; ++i) max_ring = std::max(max_ring, cloud.ring[i]);
  if (max_ring >= 4096) return std::nullopt;
  const std::size_t ring_ids = static_cast<std::size_t>(max_ring) + 1;
  const std::size_t stride = sample_stride(n, kMaxRingFieldSamples, ring_ids);

  // A ring is kept with 3 points near its mean. From a sample, unless the sample leaves a ring
  // that has 3 points in the cloud with fewer: then from every point, so sampling never drops a
  // sparse ring (one that sees little) that the whole cloud keeps.
  RingMeans means;
  means.mean.assign(ring_ids, 0);
  ring_means(cloud, elevation, stride, means);
  if (stride > 1) {
    std::vector<std::uint32_t> points(ring_ids, 0);
    for (std::size_t i = 0; i < n; ++i) ++points[cloud.ring[i]];
    bool sparse_ring = false;
    for (std::size_t r = 0; r < ring_ids; ++r) sparse_ring |= points[r] >= 3 && means.near[r] < 3;
    if (sparse_ring) ring_means(cloud, elevation, 1, means);
  }
  const std::vector<double>& mean = means.mean;
  const std::vector<std::uint32_t>& near = means.near;

  std::vector<std::uint16_t> kept;
  for (std::size_t r = 0; r < ring_ids; ++r)
    if (near[r] >= 3) kept.push_back(static_cast<std::uint16_t>(r));
  if (kept.size() < kMinRings || kept.size() > kMaxRings) return std::nullopt;
  std::sort(kept.begin(), kept.end(), [&](auto a, auto b) { return mean[a] > mean[b]; });

  RingStructure rings;
  rings.source = "ring field";
  rings.row_of_ring.assign(ring_ids, -1);
  for (std::size_t row = 0; row < kept.size(); ++row) {
    rings.elevation.push_back(mean[kept[row]]);
    rings.row_of_ring[kept[row]] = static_cast<std::int32_t>(row);
    // Two rings at one elevation are not laser cones (e.g. Livox scan lines).
    if (row > 0 && rings.elevation[row - 1] - rings.elevation[row] < 0.02 * kDeg)
      return std::nullopt;
  }

  // Cones of constant elevation: nearly every point lies close to its ring's elevation.
  const std::vector<double> band = ring_bands(rings.elevation);
  const auto [inside, total] = inside_and_total(cloud, elevation, stride, rings, band, means);
  if (total == 0 || static_cast<double>(inside) < 0.9 * static_cast<double>(total))
    return std::nullopt;
  return rings;
}

std::optional<RingStructure> rings_from_elevations(const float* elevation, std::size_t n) {
  const std::size_t stride = sample_stride(n, kMaxElevationSamples, 1);
  float lo = 10, hi = -10;
  std::size_t samples = 0;
  for (std::size_t i = 0; i < n; i += stride) {
    if (!std::isfinite(elevation[i])) continue;
    lo = std::min(lo, elevation[i]);
    hi = std::max(hi, elevation[i]);
    ++samples;
  }
  if (samples < 100) return std::nullopt;

  // Histogram at 0.02 deg: a ring fills one or two bins, its neighbours are >= 0.15 deg away.
  const double bin = 0.02 * kDeg;
  const std::size_t bins = static_cast<std::size_t>((hi - lo) / bin) + 1;
  std::vector<double> count(bins, 0), sum(bins, 0);
  for (std::size_t i = 0; i < n; i += stride) {
    if (!std::isfinite(elevation[i])) continue;
    const std::size_t b = std::min(bins - 1, static_cast<std::size_t>((elevation[i] - lo) / bin));
    count[b] += 1;
    sum[b] += elevation[i];
  }

  // Clusters: runs of bins that each hold at least 0.1 % of the points.
  const double occupied = std::max(2.0, 0.001 * static_cast<double>(samples));
  struct Cluster {
    std::size_t first, last;
    double count, sum;
  };
  std::vector<Cluster> clusters;
  double clustered = 0;
  for (std::size_t b = 0; b < bins; ++b) {
    if (count[b] < occupied) continue;
    if (!clusters.empty() && clusters.back().last + 1 == b) {
      clusters.back().last = b;
      clusters.back().count += count[b];
      clusters.back().sum += sum[b];
    } else {
      clusters.push_back({b, b, count[b], sum[b]});
    }
    clustered += count[b];
  }
  if (clusters.size() < kMinRings || clusters.size() > kMaxRings) return std::nullopt;
  if (clustered < 0.9 * static_cast<double>(samples)) return std::nullopt;

  RingStructure rings;
  rings.source = "elevation clusters";
  for (auto c = clusters.rbegin(); c != clusters.rend(); ++c)
    rings.elevation.push_back(c->sum / c->count);
  // Narrow bands far apart, as laser cones are; a dense but continuous cloud fails here.
  const std::vector<double> band = ring_bands(rings.elevation);
  for (std::size_t row = 0; row < clusters.size(); ++row) {
    const Cluster& c = clusters[clusters.size() - 1 - row];
    const double width = static_cast<double>(c.last - c.first + 1) * bin;
    if (width > 2 * band[row] + bin) return std::nullopt;
  }
  return rings;
}

RingRowLookup::RingRowLookup(const RingStructure& rings) {
  const std::vector<double>& e = rings.elevation;
  if (e.empty()) return;
  double min_gap = 1.0 * kDeg;
  for (std::size_t r = 1; r < e.size(); ++r) min_gap = std::min(min_gap, e[r - 1] - e[r]);
  const double step = std::max(min_gap / 8, 1e-5);
  const double margin = 2 * min_gap;
  start_ = static_cast<float>(e.back() - margin);
  inv_step_ = static_cast<float>(1 / step);
  const std::size_t cells =
      static_cast<std::size_t>((e.front() - e.back() + 2 * margin) / step) + 1;
  rows_.resize(cells);
  // Rows run from the highest ring (row 0) down; walk the table upwards from the lowest ring.
  std::size_t row = e.size() - 1;
  for (std::size_t i = 0; i < cells; ++i) {
    const double el = start_ + (static_cast<double>(i) + 0.5) * step;
    while (row > 0 && el > 0.5 * (e[row] + e[row - 1])) --row;
    rows_[i] = static_cast<std::int32_t>(row);
  }
}

}  // namespace iilfm
