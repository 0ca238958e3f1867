// Automatic image resolution: the angular spacing of a cloud's points, so `iilfm detect scan.pcd`
// works without a sensor preset.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "iilfm/projection.hpp"
#include "iilfm/sensor.hpp"
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

// A spinning preset's column step is that of one operating mode (an Ouster's 1024 columns of 512,
// 1024 or 2048; a Velodyne at 600 rpm of 300-1200), and a cloud from another mode projected at it
// halves the columns (or leaves every other one empty). The column step of `cloud`'s mode: its
// median azimuth step along the rings, rounded to a whole number of columns in 360 deg, when it
// differs from the preset's by more than kSameMode and less than kOtherModes times; nothing
// otherwise (the preset's mode, a non-spinning preset, a cloud without rings). For one sweep:
// sweeps integrated at other azimuth phases have finer gaps along a ring than the columns.
std::optional<double> mode_column_step(const SensorPreset& preset, const PointCloud& cloud);
inline constexpr double kSameMode = 1.25;
inline constexpr double kOtherModes = 2.2;

// How the JSON's image.resolution names a preset's resolution: "preset NAME", followed by
// ", columns from the cloud (N)" when mode_column_step gave the columns.
std::string preset_resolution_source(const std::string& preset,
                                     std::optional<double> mode_step_deg);

// Pixel size over mean point spacing for non-repetitive scans: 1.15 reproduces the paper's
// 0.05 deg for a 60-frame Mid-40 cloud, and leaves few holes inside the covered area.
inline constexpr double kDensityFactor = 1.15;

}  // namespace iilfm
