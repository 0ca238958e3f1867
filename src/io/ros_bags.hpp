// The bag readers behind open_bag.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/io/bag.hpp"

namespace iilfm::io {

std::unique_ptr<BagReader> open_ros1_bag(const std::string& path);
// The ROS 2 readers take the bag's path (for messages) and its storage files, read as one
// recording: the folder's (ros2_storage), or the path itself for a single file.
// The sqlite3 storage: .db3 files.
std::unique_ptr<BagReader> open_ros2_bag(const std::string& path,
                                         const std::vector<std::string>& files);
// MCAP files (src/io/mcap_bag.cpp).
std::unique_ptr<BagReader> open_mcap_bag(const std::string& path,
                                         const std::vector<std::string>& files);

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

// "/a [type], /b [type]", or "none"
std::string topics_with_types(const std::vector<BagTopic>& topics);

// "no topic '/x' (topics: /a [type], /b [type])"
std::string missing_topic_problem(const std::string& topic, const std::vector<BagTopic>& topics);

// What select() says of a topic no connection carries: the damage that stopped the listing before
// one did, or the topics that exist.
InputError no_topic_error(const std::string& path, const std::string& topic,
                          const std::string& damage, const std::vector<BagTopic>& topics);

// Adds a message recorded at `time_ns` to the topic's count and time span.
void count_message(BagTopic& topic, std::int64_t time_ns);

// The readers' index entries (time_ns and a connection or channel id) of the connections in `ids`,
// in time order; equal times keep their order in `entries` (file order).
template <typename Entry>
std::vector<const Entry*> in_time_order(const std::vector<Entry>& entries,
                                        const std::set<std::uint32_t>& ids,
                                        std::uint32_t Entry::*connection) {
  std::vector<const Entry*> selected;
  for (const Entry& e : entries)
    if (ids.count(e.*connection)) selected.push_back(&e);
  std::stable_sort(selected.begin(), selected.end(),
                   [](const Entry* a, const Entry* b) { return a->time_ns < b->time_ns; });
  return selected;
}

}  // namespace iilfm::io
