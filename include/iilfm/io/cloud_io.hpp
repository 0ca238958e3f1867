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
// type and count). Fields by name as PLY and PointCloud2 name them (any letter case, no "scalar_"
// prefix): intensity from intensity, signal, reflectivity or i; ring from ring, channel or line;
// per-point time from time, timestamp or t. Fields it does not know are skipped.
LoadedCloud read_pcd(const std::string& path);

// KITTI Velodyne .bin: consecutive little-endian float32 quadruples x, y, z, reflectance.
LoadedCloud read_kitti_bin(const std::string& path);

// PLY (ascii, binary_little_endian, binary_big_endian): the vertex element's x, y, z (any numeric
// type); intensity from intensity, signal, reflectivity or i, ring from ring, channel or line, time
// from time, timestamp or t, each also with CloudCompare's "scalar_" prefix and in any letter case.
LoadedCloud read_ply(const std::string& path);

// Plain text: one point per line, x y z [intensity] separated by blanks or commas; '#' starts a
// comment; one line of column names may come first; further columns are ignored.
LoadedCloud read_xyz_text(const std::string& path);

// Chooses the reader by file extension: .pcd, .bin, .ply, .txt/.xyz/.xyzi/.csv; InputError for
// anything else.
LoadedCloud read_cloud(const std::string& path);

// True when read_cloud takes files with this path's extension.
bool is_cloud_file(const std::string& path);

// The extension of the path's file name, lower-case (".pcd"; "" when it has none): how every
// reader and writer of iilfm is chosen.
std::string lower_extension(const std::string& path);

enum class PcdEncoding { kAscii, kBinary, kBinaryCompressed };

// Writes x y z intensity (float32), plus ring (uint16) and time (float64) when the cloud has them.
void write_pcd(const std::string& path, const PointCloud& cloud,
               PcdEncoding encoding = PcdEncoding::kBinary);

}  // namespace iilfm::io
