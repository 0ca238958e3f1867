// Reading and writing point cloud files. Readers skip non-finite and all-zero points and count them
// in CloudStats; any malformed file raises InputError("<path>: <problem>") and returns nothing.
#pragma once

#include <string>

#include "iilfm/types.hpp"

namespace iilfm::io {

struct LoadedCloud {
  PointCloud cloud;
  CloudStats stats;
};

// PCD (VERSION 0.7 and older headers; DATA ascii, binary and binary_compressed; any numeric field
// type and count; intensity taken from a field named intensity, reflectivity or i; ring from ring
// or channel; per-point time from time, timestamp or t). Fields it does not know are skipped.
LoadedCloud read_pcd(const std::string& path);

// KITTI Velodyne .bin: consecutive little-endian float32 quadruples x, y, z, reflectance.
LoadedCloud read_kitti_bin(const std::string& path);

// Chooses the reader by file extension (.pcd, .bin); InputError for anything else.
LoadedCloud read_cloud(const std::string& path);

enum class PcdEncoding { kAscii, kBinary, kBinaryCompressed };

// Writes x y z intensity (float32), plus ring (uint16) and time (float64) when the cloud has them.
void write_pcd(const std::string& path, const PointCloud& cloud,
               PcdEncoding encoding = PcdEncoding::kBinary);

}  // namespace iilfm::io
