#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace iilfm::cli {

ProgressBar::ProgressBar(std::size_t total, bool wanted)
    : total_(total),
      enabled_(wanted && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

ProgressBar::~ProgressBar() { finish(); }

double ProgressBar::rate(std::size_t done) const {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return seconds > 0 ? static_cast<double>(done) / seconds : 0;
}

void ProgressBar::update(std::size_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  // Redrawing at most ten times a second keeps the terminal cheap at hundreds of frames/s.
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100) && done != total_) return;
  last_draw_ = now;
  drawn_ = true;
  if (total_ > 0) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * std::min<double>(1.0, double(done) / total_));
    std::fprintf(stderr, "\r[%-*s] %zu/%zu frames, %.1f frames/s ", kWidth,
                 std::string(static_cast<std::size_t>(filled), '#').c_str(), done, total_,
                 rate(done));
  } else {
    std::fprintf(stderr, "\r%zu frames, %.1f frames/s ", done, rate(done));
  }
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace iilfm::cli
