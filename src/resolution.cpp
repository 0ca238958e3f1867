#include "iilfm/resolution.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "fast_math.hpp"
#include "iilfm/error.hpp"
#include "iilfm/ring_structure.hpp"

namespace iilfm {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

double median(std::vector<double>& values) {
  const std::size_t k = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// Median azimuth step between neighbouring points of the best-filled rings.
std::optional<double> ring_azimuth_step(const PointCloud& cloud, const std::vector<float>& azimuth,
                                        const std::vector<float>& elevation,
                                        const RingStructure& rings) {
  const std::size_t n = cloud.size();
  const bool by_field = !rings.row_of_ring.empty();
  const RingRowLookup lookup(by_field ? RingStructure{} : rings);
  std::vector<std::vector<float>> per_row(rings.rows());
  for (std::size_t i = 0; i < n; ++i) {
    int row;
    if (by_field) {
      row = cloud.ring[i] < rings.row_of_ring.size() ? rings.row_of_ring[cloud.ring[i]] : -1;
    } else {
      row = lookup.row(elevation[i]);
    }
    if (row >= 0) per_row[static_cast<std::size_t>(row)].push_back(azimuth[i]);
  }
  std::vector<double> steps;
  for (std::vector<float>& az : per_row) {
    if (az.size() < 20) continue;
    std::sort(az.begin(), az.end());
    std::vector<double> gaps;
    gaps.reserve(az.size());
    // Identical azimuths are dual returns of one beam, not a step.
    for (std::size_t k = 1; k < az.size(); ++k)
      if (az[k] - az[k - 1] > 1e-5f) gaps.push_back(az[k] - az[k - 1]);
    if (gaps.size() >= 10) steps.push_back(median(gaps));
  }
  if (steps.empty()) return std::nullopt;
  return median(steps);
}

}  // namespace

ResolutionEstimate estimate_resolution(const PointCloud& cloud) {
  const std::size_t n = cloud.size();
  std::vector<float> azimuth(n), elevation(n);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = cloud.x[i], y = cloud.y[i], z = cloud.z[i];
    azimuth[i] = detail::fast_atan2(y, x);
    elevation[i] = detail::fast_atan2(z, std::sqrt(x * x + y * y));
    valid += (x != 0 || y != 0 || z != 0) ? 1 : 0;
  }
  if (valid < 100)
    throw InputError("too few points (" + std::to_string(valid) +
                     ") to estimate the angular resolution; give --sensor or --res-h/--res-v");

  ResolutionEstimate estimate;
  std::optional<RingStructure> rings = rings_from_field(cloud, elevation.data());
  if (!rings) rings = rings_from_elevations(elevation.data(), n);
  if (rings) {
    if (const auto step = ring_azimuth_step(cloud, azimuth, elevation, *rings)) {
      estimate.res_h_deg = *step * kRadToDeg;
      estimate.res_v_deg = rings->mean_spacing() * kRadToDeg;
      estimate.rows = RowLayout::kRings;
      estimate.rings = rings->rows();
      estimate.method = rings->source;
      return estimate;
    }
  }

  // Covered field of view: cells of a coarse angular grid holding points.
  constexpr double kCellDeg = 0.5;
  const AngularBounds extent = angular_extent(cloud);
  const double cell = kCellDeg / kRadToDeg;
  const std::size_t cols =
      static_cast<std::size_t>((extent.azimuth_max - extent.azimuth_min) / cell) + 1;
  const std::size_t cell_rows =
      static_cast<std::size_t>((extent.elevation_max - extent.elevation_min) / cell) + 1;
  std::vector<std::uint8_t> covered(cols * cell_rows, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (cloud.x[i] == 0 && cloud.y[i] == 0 && cloud.z[i] == 0) continue;
    const std::size_t c =
        std::min(cols - 1,
                 static_cast<std::size_t>(std::max(0.0, (azimuth[i] - extent.azimuth_min) / cell)));
    const std::size_t r = std::min(
        cell_rows - 1,
        static_cast<std::size_t>(std::max(0.0, (elevation[i] - extent.elevation_min) / cell)));
    covered[r * cols + c] = 1;
  }
  const double area_deg2 =
      static_cast<double>(std::count(covered.begin(), covered.end(), 1)) * kCellDeg * kCellDeg;
  const double spacing = std::sqrt(area_deg2 / static_cast<double>(valid));
  estimate.res_h_deg = estimate.res_v_deg = std::clamp(kDensityFactor * spacing, 0.01, 2.0);
  estimate.method = "point density";
  return estimate;
}

std::optional<double> mode_column_step(const SensorPreset& preset, const PointCloud& cloud) {
  if (preset.kind != ScanKind::kSpinning || !(preset.res_h_deg > 0)) return std::nullopt;
  ResolutionEstimate measured;
  try {
    measured = estimate_resolution(cloud);
  } catch (const InputError&) {
    return std::nullopt;  // too few points to tell: the preset's step
  }
  if (measured.rows != RowLayout::kRings || !(measured.res_h_deg > 0)) return std::nullopt;
  const double ratio = measured.res_h_deg / preset.res_h_deg;
  if (ratio < kSameMode && ratio > 1 / kSameMode) return std::nullopt;
  if (ratio > kOtherModes || ratio < 1 / kOtherModes) return std::nullopt;
  return 360.0 / std::round(360.0 / measured.res_h_deg);
}

std::string preset_resolution_source(const std::string& preset,
                                     std::optional<double> mode_step_deg) {
  std::string source = "preset " + preset;
  if (mode_step_deg)
    source +=
        ", columns from the cloud (" + std::to_string(std::lround(360.0 / *mode_step_deg)) + ")";
  return source;
}

}  // namespace iilfm
