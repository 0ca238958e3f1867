// A one-line progress bar with the processing rate, redrawn in place on stderr. Silent unless
// stderr is a terminal, so logs and pipes get no control characters.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace iilfm::cli {

class ProgressBar {
 public:
  // `total` 0: unknown length (the count and rate only). `wanted` false: never draws.
  ProgressBar(std::size_t total, bool wanted);
  ~ProgressBar();

  void update(std::size_t done);
  // Clears the line (call before printing anything else on stderr).
  void finish();
  // Frames per second since construction.
  double rate(std::size_t done) const;

 private:
  std::size_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace iilfm::cli
