// Shared by the fuzz targets: the readers take paths, so each input is written to one scratch file
// of this process (in /dev/shm when it exists, to spare the disk) before the reader opens it.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace iilfm::fuzz {

// Writes the input to this process's scratch file with the given extension (".pcd") and returns
// its path. Aborts when the file cannot be written: that is the harness failing, not the reader.
inline std::string write_input(const std::uint8_t* data, std::size_t size, const char* extension) {
  namespace fs = std::filesystem;
  static const fs::path dir =
      fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
  const std::string path = (dir / ("iilfm_fuzz_" + std::to_string(getpid()) + extension)).string();
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file || (size > 0 && std::fwrite(data, 1, size, file) != size) || std::fclose(file) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
  return path;
}

// Removes the scratch file when the process ends.
struct ScratchFile {
  std::string path;
  ~ScratchFile() {
    if (!path.empty()) std::remove(path.c_str());
  }
};

}  // namespace iilfm::fuzz
