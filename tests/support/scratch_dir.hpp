// Temporary directories for tests that write files. ctest runs every test in a process of its
// own, so a directory named after the process and never removed would leave one behind per test
// run (thousands in /tmp after a few days of work); these remove themselves.
#pragma once

#include <stdlib.h>  // mkdtemp

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace iilfm::testing {

// A fresh directory under the system's temp directory, removed with everything in it when the
// object goes.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix = "iilfm_test") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
    dir_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return dir_; }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

 private:
  std::filesystem::path dir_;
};

// One directory for the whole test process, removed when the process exits normally.
inline const std::filesystem::path& process_scratch_dir() {
  static const ScratchDir dir("iilfm_test");
  return dir.path();
}

}  // namespace iilfm::testing
