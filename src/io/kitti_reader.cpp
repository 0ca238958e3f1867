// read_kitti_bin: headerless float32 records x, y, z, reflectance.
#include <algorithm>

#include "file_bytes.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "point_filter.hpp"
#include "scalar_column.hpp"

namespace iilfm::io {

LoadedCloud read_kitti_bin(const std::string& path) {
  constexpr std::size_t kRecordSize = 4 * sizeof(float);
  const FileBytes file = read_file_bytes(path);
  if (file.size() % kRecordSize != 0) {
    throw file_error(path, "KITTI .bin size " + std::to_string(file.size()) +
                               " bytes is not a multiple of 16 (float32 x, y, z, reflectance)");
  }
  const std::size_t n = file.size() / kRecordSize;
  LoadedCloud loaded;
  loaded.cloud.reserve(n);
  loaded.stats.points_in_file = n;
  for (std::size_t first = 0; first < n; first += kDecodeBlockPoints) {
    const std::size_t count = std::min(kDecodeBlockPoints, n - first);
    const std::size_t slot = grow_columns(loaded.cloud, count, false, false);
    const std::uint8_t* records = file.begin() + first * kRecordSize;
    PointCloud& cloud = loaded.cloud;
    decode_column(ScalarType::kF32, records, kRecordSize, count, cloud.x.data() + slot);
    decode_column(ScalarType::kF32, records + 4, kRecordSize, count, cloud.y.data() + slot);
    decode_column(ScalarType::kF32, records + 8, kRecordSize, count, cloud.z.data() + slot);
    decode_column(ScalarType::kF32, records + 12, kRecordSize, count,
                  cloud.intensity.data() + slot);
    drop_invalid_points(cloud, slot, loaded.stats);
  }
  return loaded;
}

}  // namespace iilfm::io
