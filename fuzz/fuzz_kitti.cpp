// Fuzz target: the KITTI .bin reader on arbitrary bytes. InputError is the one accepted failure; a
// cloud that comes back must satisfy check_cloud.
#include <cstddef>
#include <cstdint>

#include "cloud_checks.hpp"
#include "fuzz_input.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static iilfm::fuzz::ScratchFile scratch;
  scratch.path = iilfm::fuzz::write_input(data, size, ".bin");
  try {
    iilfm::fuzz::check_cloud(iilfm::io::read_kitti_bin(scratch.path));
  } catch (const iilfm::InputError&) {
  }
  return 0;
}
