// Automatic image resolution: the angular spacing of a cloud's points, so `iilfm detect scan.pcd`
// works without a sensor preset.
#pragma once

#include <cstddef>
#include <string>

#include "iilfm/projection.hpp"
#include "iilfm/types.hpp"

namespace iilfm {

struct ResolutionEstimate {
  double res_h_deg = 0;  // column spacing
  double res_v_deg = 0;  // row spacing (mean ring spacing for ring rows)
  RowLayout rows = RowLayout::kUniform;
  std::size_t rings = 0;  // rings found (spinning LiDARs)
  std::string method;     // "ring field", "elevation clusters" or "point density"
};

// Spinning LiDARs (rings in the ring field or in the elevations): one row per ring and the median
// azimuth step between neighbouring points of a ring. Anything else (Livox rosettes, integrated
// or merged clouds): square pixels of kDensityFactor times the mean angular point spacing over
// the covered field of view. InputError when the cloud has too few points to tell.
ResolutionEstimate estimate_resolution(const PointCloud& cloud);

// Pixel size over mean point spacing for non-repetitive scans: 1.15 reproduces the paper's
// 0.05 deg for a 60-frame Mid-40 cloud, and leaves few holes inside the covered area.
inline constexpr double kDensityFactor = 1.15;

}  // namespace iilfm
