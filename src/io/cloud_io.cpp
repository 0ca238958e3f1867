// read_cloud: picks the reader from the file extension.
#include "iilfm/io/cloud_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "iilfm/error.hpp"

namespace iilfm::io {

LoadedCloud read_cloud(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::string lower = extension;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == ".pcd") return read_pcd(path);
  if (lower == ".bin") return read_kitti_bin(path);
  const std::string shown = extension.empty() ? "(no extension)" : "'" + extension + "'";
  throw file_error(path, "unsupported cloud format " + shown + " (supported: .pcd, .bin)");
}

}  // namespace iilfm::io
