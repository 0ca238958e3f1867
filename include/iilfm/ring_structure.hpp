// The rings of a spinning LiDAR: which elevation each laser scans, found from the ring field or
// from the elevation distribution alone. Ring-aware projection gives every ring its own image row,
// so non-uniform rings (VLP-32C, Pandar64) neither collide nor leave empty rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm {

struct RingStructure {
  std::vector<double> elevation;  // one per image row, radians, strictly decreasing
  // Ring field value -> row, -1 for rings without (enough) points. Empty when the rings were found
  // from the elevations; then a point's row is the ring nearest to its elevation.
  std::vector<std::int32_t> row_of_ring;
  std::string source;  // "ring field" or "elevation clusters"

  std::size_t rows() const { return elevation.size(); }
  double mean_spacing() const;  // radians between neighbouring rows
};

// Rings from the cloud's ring field, given each point's elevation (radians). std::nullopt when the
// cloud has no ring field, or when its rings are not cones of near-constant elevation (Livox
// "line" numbers, a cloud transformed out of the sensor frame): then rows must stay uniform.
std::optional<RingStructure> rings_from_field(const PointView& cloud, const float* elevation);

// Rings from the elevations alone: points concentrated in narrow, well separated elevation bands,
// as a spinning LiDAR's are. std::nullopt for anything else (a Livox rosette, a dense mesh).
std::optional<RingStructure> rings_from_elevations(const float* elevation, std::size_t n);

// Maps elevations to the nearest ring's row with one table look-up per point.
class RingRowLookup {
 public:
  explicit RingRowLookup(const RingStructure& rings);
  int row(float elevation) const {
    const float t = (elevation - start_) * inv_step_;
    if (!(t >= 0.0f)) return rows_.empty() ? -1 : rows_.front();
    const std::size_t i = static_cast<std::size_t>(t);
    return i < rows_.size() ? rows_[i] : rows_.back();
  }

 private:
  float start_ = 0, inv_step_ = 1;
  std::vector<std::int32_t> rows_;
};

}  // namespace iilfm
