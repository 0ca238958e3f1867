// Splitting a pass over items between threads so that its result does not depend on how many:
// each part owns a contiguous range of the items and writes only its own results.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "task_threads.hpp"

namespace iilfm::detail {

constexpr int kMaxParts = 64;

// How many parts `items` splits into for `threads` threads, each at least `min_per_part` long
// (below that, a thread's start costs more than it saves).
inline int parts_for(int threads, std::size_t items, std::size_t min_per_part) {
  const std::size_t most = std::max<std::size_t>(1, items / std::max<std::size_t>(1, min_per_part));
  const auto wanted = static_cast<std::size_t>(std::clamp(threads, 1, kMaxParts));
  return static_cast<int>(std::min(wanted, most));
}

// [begin, end) of part k of `items` split into `parts` (sizes differ by at most one).
inline std::pair<std::size_t, std::size_t> part_range(std::size_t items, int k, int parts) {
  const auto n = static_cast<std::size_t>(parts);
  const auto share = [&](int i) {
    const auto j = static_cast<std::size_t>(i);
    return items / n * j + items % n * j / n;
  };
  return {share(k), share(k + 1)};
}

// Calls part(k, parts) for k = 0 .. parts - 1 on this thread and the process's part threads
// (part_threads), kept from call to call: starting a thread and its thread-local scratch anew
// cost about 45 us a call here, waking a kept one 6-9 us. While those serve another call (another
// caller's, or one made inside a part), on this thread and new ones (this thread alone when the
// system refuses them). Any part may run on any thread: none may rely on the caller's
// thread-locals. `part` must not throw.
template <typename Part>
void in_parts(int parts, const Part& part) {
  if (parts <= 1) {
    part(0, 1);
    return;
  }
  const Part* const each = &part;
  const std::function<void(std::size_t)> task = [each, parts](std::size_t k) {
    (*each)(static_cast<int>(k), parts);
  };
  if (part_threads().try_run(static_cast<std::size_t>(parts), task)) return;
  std::vector<std::thread> helpers;
  helpers.reserve(static_cast<std::size_t>(parts - 1));
  int started = 1;
  try {
    for (; started < parts; ++started)
      helpers.emplace_back([&part, started, parts] { part(started, parts); });
  } catch (const std::system_error&) {
  }
  for (int k = started; k < parts; ++k) part(k, parts);
  part(0, parts);
  for (std::thread& t : helpers) t.join();
}

// Calls pass(first_row, end_row) for `parts` contiguous ranges of an image's `rows`, each on its
// own thread (in_parts); a pass writes only its own rows.
template <typename Pass>
void in_row_parts(int rows, int parts, const Pass& pass) {
  in_parts(parts, [&](int k, int count) {
    const auto [first, end] = part_range(static_cast<std::size_t>(rows), k, count);
    pass(static_cast<int>(first), static_cast<int>(end));
  });
}

}  // namespace iilfm::detail
