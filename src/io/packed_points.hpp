// Points stored as fixed-size records with named numeric fields at byte offsets: the body of a
// sensor_msgs/PointCloud2 and of a binary PLY vertex element. One decoder for both, either byte
// order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "iilfm/io/cloud_io.hpp"
#include "scalar_column.hpp"

namespace iilfm::io {

struct PackedField {
  std::string name;
  ScalarType type;
  std::size_t offset;  // within the record
};

std::size_t scalar_size(ScalarType type);

// Which field feeds each cloud column; kAbsent when none does.
struct PackedRoles {
  static constexpr int kAbsent = -1;
  int x = kAbsent, y = kAbsent, z = kAbsent, intensity = kAbsent, ring = kAbsent, time = kAbsent;
  bool has_xyz() const { return x >= 0 && y >= 0 && z >= 0; }
};

// Picks the fields by name, case-insensitively and ignoring a "scalar_" prefix (CloudCompare's):
// x, y, z; intensity from intensity, else signal (an Ouster's photon count under its driver's
// native point type, which "intensity" holds under the default one), else reflectivity, else i;
// ring from ring, else channel, else line; time from time, else timestamp, else t. Earlier names
// win over later ones. Every reader of named fields (PCD, PLY, PointCloud2) uses these rules.
PackedRoles find_roles_by_name(const std::vector<std::string>& names);
PackedRoles find_packed_roles(const std::vector<PackedField>& fields);

// Appends `n` records, the first at `first` and each next one `stride` bytes further, to out
// (invalid points dropped and counted, points_in_file += n). The caller has checked that every
// field of every record lies inside the data.
void decode_packed_records(const std::uint8_t* first, std::size_t n, std::size_t stride,
                           const std::vector<PackedField>& fields, const PackedRoles& roles,
                           bool big_endian, LoadedCloud& out);

}  // namespace iilfm::io
