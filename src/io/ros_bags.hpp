// The bag readers behind open_bag.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "iilfm/io/bag.hpp"

namespace iilfm::io {

std::unique_ptr<BagReader> open_ros1_bag(const std::string& path);
// A ROS 2 bag in the sqlite3 storage: a folder, or one .db3 file.
std::unique_ptr<BagReader> open_ros2_bag(const std::string& path);
// MCAP: one .mcap file, or a ROS 2 bag folder in the mcap storage (src/io/mcap_bag.cpp).
std::unique_ptr<BagReader> open_mcap_bag(const std::string& path);

// A ROS 2 bag folder's storage plugin ("sqlite3", "mcap", ...) and files, from its metadata.yaml;
// without one, the folder's .db3 and .mcap files in name order.
struct Ros2Storage {
  std::string identifier;
  std::vector<std::string> files;
};
Ros2Storage ros2_storage(const std::string& folder);

// Text from a recording (topic and type names) with control bytes replaced by '?', so a damaged
// name cannot break a one-line message or the terminal.
std::string printable(std::string_view text);

// "no topic '/x' (topics: /a [type], /b [type])"
std::string missing_topic_problem(const std::string& topic, const std::vector<BagTopic>& topics);

}  // namespace iilfm::io
