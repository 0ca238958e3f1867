// Fuzz target: the MCAP reader on arbitrary bytes: open (summary or scan), walk every topic, decode
// every point cloud message.
#include <cstddef>
#include <cstdint>

#include "bag_walk.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static iilfm::fuzz::ScratchFile scratch;
  scratch.path = iilfm::fuzz::write_input(data, size, ".mcap");
  iilfm::fuzz::walk_bag(scratch.path);
  return 0;
}
