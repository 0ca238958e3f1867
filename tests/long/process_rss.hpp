// The resident set size of this process, from /proc/self/statm (Linux), for memory-growth tests.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <fstream>

namespace iilfm::testing {

// Bytes resident now; 0 where /proc is unavailable.
inline std::size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t total_pages = 0, resident_pages = 0;
  if (!(statm >> total_pages >> resident_pages)) return 0;
  return resident_pages * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

// AddressSanitizer keeps freed memory in quarantine, so RSS grows without a leak; its
// LeakSanitizer checks leaks instead.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitizedMemory = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
constexpr bool kSanitizedMemory = true;
#else
constexpr bool kSanitizedMemory = false;
#endif
#else
constexpr bool kSanitizedMemory = false;
#endif

}  // namespace iilfm::testing
