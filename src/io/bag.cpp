// open_bag (a ROS 1 .bag file, a ROS 2 bag folder or .db3 file, an MCAP file) and what the bag
// readers share.
#include <filesystem>

#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "ros_bags.hpp"

namespace iilfm::io {

std::string printable(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) c = '?';
  }
  return out;
}

std::string topics_with_types(const std::vector<BagTopic>& topics) {
  std::string known;
  for (const BagTopic& t : topics)
    known += (known.empty() ? "" : ", ") + t.name + " [" + t.type + "]";
  return known.empty() ? "none" : known;
}

std::string missing_topic_problem(const std::string& topic, const std::vector<BagTopic>& topics) {
  return "no topic '" + topic + "' (topics: " + topics_with_types(topics) + ")";
}

InputError no_topic_error(const std::string& path, const std::string& topic,
                          const std::string& damage, const std::vector<BagTopic>& topics) {
  if (!damage.empty()) return file_error(path, damage + "; no " + topic + " message before it");
  return file_error(path, missing_topic_problem(topic, topics));
}

void count_message(BagTopic& topic, std::int64_t time_ns) {
  if (topic.messages == 0 || time_ns < topic.first_ns) topic.first_ns = time_ns;
  if (topic.messages == 0 || time_ns > topic.last_ns) topic.last_ns = time_ns;
  ++topic.messages;
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
  if (fs::is_directory(path)) {
    // metadata.yaml read once, here: its plugin picks the reader, its files go to it.
    const Ros2Storage storage = ros2_storage(path);
    if (storage.identifier == "mcap") return open_mcap_bag(path, storage.files);
    if (storage.identifier != "sqlite3")
      throw file_error(path, "ROS 2 storage '" + storage.identifier +
                                 "' is not supported (supported: sqlite3, mcap)");
    return open_ros2_bag(path, storage.files);
  }
  if (lower_extension(path) == ".db3") return open_ros2_bag(path, {path});
  if (lower_extension(path) == ".mcap") return open_mcap_bag(path, {path});
  return open_ros1_bag(path);
}

}  // namespace iilfm::io
