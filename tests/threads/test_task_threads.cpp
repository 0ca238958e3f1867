// detail::TaskThreads (src/task_threads.hpp): every task of a run exactly once, run after run on
// the same threads, and the run returns only when all are done. Under ThreadSanitizer in CI.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <set>
#include <thread>
#include <vector>

#include "../../src/task_threads.hpp"

namespace iilfm::detail {
namespace {

TEST(TaskThreads, EveryTaskRunsOnceInEveryRun) {
  for (const int helpers : {0, 1, 3}) {
    TaskThreads threads(helpers);
    for (int run = 0; run < 200; ++run) {
      const std::size_t count = 1 + static_cast<std::size_t>(run % 7);
      std::vector<int> times(count, 0);  // each slot written by the one thread running its task
      threads.run(count, [&](std::size_t i) { ++times[i]; });
      for (std::size_t i = 0; i < count; ++i)
        EXPECT_EQ(times[i], 1) << helpers << " helpers, run " << run << ", task " << i;
    }
  }
}

TEST(TaskThreads, TasksShareTheHelpersAndTheCallersThread) {
  // Two tasks that each wait for the other to start can only finish when they run at once.
  TaskThreads threads(1);
  for (int run = 0; run < 20; ++run) {
    std::atomic<int> started{0};
    std::set<std::thread::id> ids;
    std::vector<std::thread::id> id_of(2);
    threads.run(2, [&](std::size_t i) {
      id_of[i] = std::this_thread::get_id();
      ++started;
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (started < 2 && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
    });
    EXPECT_EQ(started, 2);
    ids.insert(id_of.begin(), id_of.end());
    EXPECT_EQ(ids.size(), 2u) << "run " << run;
  }
}

}  // namespace
}  // namespace iilfm::detail
