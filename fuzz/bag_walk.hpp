// Shared by the bag fuzz targets: opens a recording, walks every topic's messages to the end and
// decodes the point-cloud ones, as `iilfm detect --topic` and `iilfm bag` would. InputError (from
// the open, a message or a decode) is the one accepted failure.
#pragma once

#include <string>

#include "cloud_checks.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/bag.hpp"

namespace iilfm::fuzz {

inline void walk_bag(const std::string& path) {
  std::unique_ptr<io::BagReader> bag;
  try {
    bag = io::open_bag(path);
  } catch (const InputError&) {
    return;
  }
  for (const io::BagTopic& topic : bag->topics()) {
    try {
      bag->select(topic.name);
      io::BagMessage message;
      while (bag->next(message)) {
        if (io::is_cloud_message_type(message.type))
          check_cloud(io::decode_cloud_message(message, "fuzz").loaded);
      }
    } catch (const InputError&) {
    }
  }
}

}  // namespace iilfm::fuzz
