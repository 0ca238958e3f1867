// read_cloud: picks the reader from the file extension.
#include "iilfm/io/cloud_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "iilfm/error.hpp"

namespace iilfm::io {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

namespace {

enum class CloudFormat { kUnknown, kPcd, kKitti, kPly, kText };

CloudFormat format_of(const std::string& path) {
  const std::string lower = lower_extension(path);
  if (lower == ".pcd") return CloudFormat::kPcd;
  if (lower == ".bin") return CloudFormat::kKitti;
  if (lower == ".ply") return CloudFormat::kPly;
  if (lower == ".txt" || lower == ".xyz" || lower == ".xyzi" || lower == ".csv")
    return CloudFormat::kText;
  return CloudFormat::kUnknown;
}

}  // namespace

bool is_cloud_file(const std::string& path) { return format_of(path) != CloudFormat::kUnknown; }

LoadedCloud read_cloud(const std::string& path) {
  switch (format_of(path)) {
    case CloudFormat::kPcd:
      return read_pcd(path);
    case CloudFormat::kKitti:
      return read_kitti_bin(path);
    case CloudFormat::kPly:
      return read_ply(path);
    case CloudFormat::kText:
      return read_xyz_text(path);
    case CloudFormat::kUnknown:
      break;
  }
  const std::string extension = std::filesystem::path(path).extension().string();
  const std::string shown = extension.empty() ? "(no extension)" : "'" + extension + "'";
  throw file_error(path, "unsupported cloud format " + shown +
                             " (supported: .pcd, .bin, .ply, .txt, .xyz, .xyzi, .csv)");
}

}  // namespace iilfm::io
