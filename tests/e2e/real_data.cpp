#include "real_data.hpp"

#include <algorithm>

namespace iilfm::testing {

namespace fs = std::filesystem;

fs::path real_data_dir() { return fs::path(IILFM_SOURCE_DIR) / ".." / "shared" / "data" / "real"; }

std::vector<fs::path> pandar64_scans() {
  std::vector<fs::path> scans;
  for (const char* folder : {"opencalib_jointcalib_pandar64", "opencalib_factory_pandar64"}) {
    if (!fs::is_directory(real_data_dir() / folder)) continue;
    for (const auto& entry : fs::directory_iterator(real_data_dir() / folder))
      if (entry.path().extension() == ".pcd") scans.push_back(entry.path());
  }
  std::sort(scans.begin(), scans.end());
  return scans;
}

}  // namespace iilfm::testing
