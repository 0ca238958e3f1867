// Fuzz target: the ROS 1 bag (v2.0, none/bz2/lz4 chunks) reader on arbitrary bytes: open, walk
// every topic, decode every point cloud message.
#include <cstddef>
#include <cstdint>

#include "bag_walk.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static iilfm::fuzz::ScratchFile scratch;
  scratch.path = iilfm::fuzz::write_input(data, size, ".bag");
  iilfm::fuzz::walk_bag(scratch.path);
  return 0;
}
