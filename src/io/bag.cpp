// open_bag: a ROS 1 .bag file, a ROS 2 bag (folder, .db3 file) or an MCAP file.
#include <filesystem>

#include "iilfm/error.hpp"
#include "ros_bags.hpp"

namespace iilfm::io {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

std::string printable(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) c = '?';
  }
  return out;
}

bool is_bag_path(const std::string& path) {
  namespace fs = std::filesystem;
  if (fs::is_directory(path)) return fs::exists(fs::path(path) / "metadata.yaml");
  const std::string ext = lower_extension(path);
  return ext == ".bag" || ext == ".db3" || ext == ".mcap";
}

std::unique_ptr<BagReader> open_bag(const std::string& path) {
  namespace fs = std::filesystem;
  if (!fs::exists(path)) throw file_error(path, "no such file or folder");
  if (fs::is_directory(path))
    return ros2_storage(path).identifier == "mcap" ? open_mcap_bag(path) : open_ros2_bag(path);
  if (lower_extension(path) == ".db3") return open_ros2_bag(path);
  if (lower_extension(path) == ".mcap") return open_mcap_bag(path);
  return open_ros1_bag(path);
}

}  // namespace iilfm::io
