// The two bag readers behind open_bag.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "iilfm/io/bag.hpp"

namespace iilfm::io {

std::unique_ptr<BagReader> open_ros1_bag(const std::string& path);
std::unique_ptr<BagReader> open_ros2_bag(const std::string& path);

// Text from a recording (topic and type names) with control bytes replaced by '?', so a damaged
// name cannot break a one-line message or the terminal.
std::string printable(std::string_view text);

// "no topic '/x' (topics: /a [type], /b [type])"
std::string missing_topic_problem(const std::string& topic, const std::vector<BagTopic>& topics);

}  // namespace iilfm::io
