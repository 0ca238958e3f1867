// Recordings without ROS: ROS 1 bags (format 2.0), ROS 2 bags (sqlite3 or mcap storage) and MCAP
// files, read directly from the files, and the point-cloud messages in them decoded into clouds.
//
// A BagReader lists the topics and walks one topic's messages in time order. Damage (a truncated
// file, a corrupt chunk) is reported by the call that reaches it, so every message before it can
// still be used; the error is an InputError "<path>: <problem>".
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "iilfm/io/cloud_io.hpp"

namespace iilfm::io {

struct BagTopic {
  std::string name;
  std::string type;  // e.g. sensor_msgs/PointCloud2 (ROS 1) or sensor_msgs/msg/PointCloud2 (ROS 2)
  std::size_t messages = 0;
  std::int64_t first_ns = 0, last_ns = 0;  // record times of the first and last message
  std::string definition;                  // ROS 1 message definition from the connection record
};

enum class MessageEncoding { kRos1, kCdr };

// One message as stored. `data` stays valid until the next call to BagReader::next.
struct BagMessage {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  std::int64_t stamp_ns = 0;  // record (receive) time
  std::string type;
  MessageEncoding encoding = MessageEncoding::kRos1;
};

class BagReader {
 public:
  virtual ~BagReader() = default;

  virtual const std::string& path() const = 0;
  // "ROS 1 bag v2.0, 3 chunks (lz4), indexed" and the like.
  virtual std::string format() const = 0;
  virtual const std::vector<BagTopic>& topics() const = 0;
  // Non-empty when the reader found damage while opening (ROS 1: the index is missing or broken
  // and the scan of the chunks stopped early). Messages before the damage are still listed; next()
  // raises this problem after the last of them.
  virtual const std::string& damage() const = 0;

  // Starts walking `topic`. InputError naming the topics that exist when there is no such topic.
  virtual void select(const std::string& topic) = 0;
  // The selected topic's next message, in time order; false after the last one. InputError when
  // the message cannot be read.
  virtual bool next(BagMessage& message) = 0;
};

// A ROS 1 bag (.bag), a ROS 2 bag folder (metadata.yaml and .db3 or .mcap files), a single .db3
// file or a single .mcap file (ROS 2 CDR or ROS 1 messages).
std::unique_ptr<BagReader> open_bag(const std::string& path);

// True for paths open_bag takes: a .bag, .db3 or .mcap file, or a folder with metadata.yaml.
bool is_bag_path(const std::string& path);

// The message types decode_cloud_message knows, ROS 1 and ROS 2 spellings.
bool is_cloud_message_type(const std::string& type);
std::string cloud_message_types();  // for error messages: "sensor_msgs/PointCloud2, ..."

struct CloudMessage {
  LoadedCloud loaded;
  std::int64_t header_stamp_ns = 0;  // std_msgs/Header stamp of the message
};

// Decodes sensor_msgs/PointCloud2 (any field layout, either byte order, padding, row_step) or
// livox_ros_driver(2)/CustomMsg. `context` (e.g. "rec.bag: /points message 12") starts the message
// of the InputError raised for a malformed message or a type that is not a point cloud.
CloudMessage decode_cloud_message(const BagMessage& message, const std::string& context);

}  // namespace iilfm::io
