// A ROS 2 bag folder's metadata.yaml: which storage plugin wrote it and its files.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#include "iilfm/error.hpp"
#include "ros_bags.hpp"

namespace iilfm::io {

Ros2Storage ros2_storage(const std::string& folder) {
  namespace fs = std::filesystem;
  const fs::path metadata = fs::path(folder) / "metadata.yaml";
  Ros2Storage storage;
  if (fs::exists(metadata)) {
    try {
      const YAML::Node info = YAML::LoadFile(metadata.string())["rosbag2_bagfile_information"];
      if (!info) throw file_error(metadata.string(), "no rosbag2_bagfile_information");
      // rosbag2 before Iron wrote sqlite3 bags and named the plugin only from Foxy on.
      storage.identifier = info["storage_identifier"].as<std::string>("sqlite3");
      for (const YAML::Node& f : info["relative_file_paths"])
        storage.files.push_back((fs::path(folder) / f.as<std::string>()).string());
    } catch (const YAML::Exception& e) {
      throw file_error(metadata.string(), std::string("bad metadata: ") + e.what());
    }
    return storage;
  }
  // No metadata: the folder's storage files, in name order (rosbag2 numbers its splits).
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".db3" || ext == ".mcap") storage.files.push_back(entry.path().string());
  }
  std::sort(storage.files.begin(), storage.files.end());
  const bool any_mcap = std::any_of(storage.files.begin(), storage.files.end(), [](const auto& f) {
    return fs::path(f).extension() == ".mcap";
  });
  storage.identifier = any_mcap ? "mcap" : "sqlite3";
  return storage;
}

}  // namespace iilfm::io
