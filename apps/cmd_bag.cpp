// `iilfm bag info FILE`: what a recording holds (topics, types, message counts, time span).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/bag.hpp"

namespace iilfm::cli {
namespace {

double seconds(std::int64_t ns) {
  return static_cast<double>(ns / 1'000'000'000) + static_cast<double>(ns % 1'000'000'000) * 1e-9;
}

// Exact "sec.nanosec": a double would print 59.900000095 for 59.9 s after 1.6e9 s.
std::string stamp_text(std::int64_t ns) {
  char text[32];
  std::snprintf(text, sizeof text, "%lld.%09lld", static_cast<long long>(ns / 1'000'000'000),
                static_cast<long long>(ns % 1'000'000'000));
  return text;
}

int run_bag_info(const std::string& path) {
  const std::unique_ptr<io::BagReader> bag = io::open_bag(path);
  const std::vector<io::BagTopic>& topics = bag->topics();
  std::size_t total = 0, name_width = 5, type_width = 4;
  std::int64_t first = 0, last = 0;
  bool any = false;
  for (const io::BagTopic& t : topics) {
    total += t.messages;
    name_width = std::max(name_width, t.name.size());
    type_width = std::max(type_width, t.type.size());
    if (t.messages == 0) continue;
    first = any ? std::min(first, t.first_ns) : t.first_ns;
    last = any ? std::max(last, t.last_ns) : t.last_ns;
    any = true;
  }
  std::printf("path:     %s\nformat:   %s\n", path.c_str(), bag->format().c_str());
  if (any)
    std::printf("duration: %.3f s (%s to %s)\n", seconds(last - first), stamp_text(first).c_str(),
                stamp_text(last).c_str());
  std::printf("messages: %zu\ntopics:   %zu\n", total, topics.size());
  for (const io::BagTopic& t : topics) {
    const double span = seconds(t.last_ns - t.first_ns);
    std::printf("  %-*s  %-*s  %7zu msgs", static_cast<int>(name_width), t.name.c_str(),
                static_cast<int>(type_width), t.type.c_str(), t.messages);
    if (t.messages > 1 && span > 0) std::printf("  %7.2f Hz", (t.messages - 1) / span);
    if (io::is_cloud_message_type(t.type)) std::printf("  (point cloud)");
    std::printf("\n");
  }
  std::fflush(stdout);
  if (!bag->damage().empty())
    throw file_error(path, bag->damage() + " (the listing covers the messages before it)");
  return 0;
}

}  // namespace

Runner register_bag_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* bag = app.add_subcommand("bag",
                                     "Inspect recordings (ROS 1 .bag, ROS 2 bag folder, .db3 "
                                     "or .mcap)");
  bag->require_subcommand(1);
  CLI::App* info = bag->add_subcommand("info", "List topics, types, message counts and time span");
  info->add_option("file", *path, "ROS 1 .bag, ROS 2 bag folder, .db3 or .mcap file")->required();
  return [path] { return run_bag_info(*path); };
}

}  // namespace iilfm::cli
