// What every cloud a reader returns must satisfy, whatever the file held: columns of one length,
// only finite, non-zero points kept, and the skipped points counted. A violation aborts, so the
// fuzzer reports it like a crash.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "iilfm/io/cloud_io.hpp"

namespace iilfm::fuzz {

inline void require(bool condition, const char* what) {
  if (!condition) {
    std::fprintf(stderr, "cloud invariant broken: %s\n", what);
    std::abort();
  }
}

inline void check_cloud(const io::LoadedCloud& loaded) {
  const PointCloud& c = loaded.cloud;
  const std::size_t n = c.size();
  require(c.y.size() == n && c.z.size() == n && c.intensity.size() == n, "column lengths differ");
  require(c.ring.empty() || c.ring.size() == n, "ring column length");
  require(c.time.empty() || c.time.size() == n, "time column length");
  require(loaded.stats.valid_points == n, "valid_points != cloud size");
  require(loaded.stats.valid_points + loaded.stats.non_finite + loaded.stats.zero <=
              loaded.stats.points_in_file,
          "more points counted than the file holds");
  for (std::size_t i = 0; i < n; ++i) {
    require(std::isfinite(c.x[i]) && std::isfinite(c.y[i]) && std::isfinite(c.z[i]) &&
                std::isfinite(c.intensity[i]),
            "non-finite point kept");
    require(c.x[i] != 0 || c.y[i] != 0 || c.z[i] != 0, "all-zero point kept");
  }
}

}  // namespace iilfm::fuzz
