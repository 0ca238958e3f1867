// detail::TaskThreads (src/task_threads.hpp): every task of a run exactly once, run after run on
// the same threads, and the run returns only when all are done. Under ThreadSanitizer in CI.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <set>
#include <thread>
#include <vector>

#include "../../src/parallel_parts.hpp"
#include "../../src/task_threads.hpp"

namespace iilfm::detail {
namespace {

// Counts this task as started, then waits (ten seconds at most) until `all` have: tasks that can
// only finish when they run at once.
void start_and_wait_for_all(std::atomic<int>& started, int all) {
  ++started;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (started < all && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
}

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
      start_and_wait_for_all(started, 2);
    });
    EXPECT_EQ(started, 2);
    ids.insert(id_of.begin(), id_of.end());
    EXPECT_EQ(ids.size(), 2u) << "run " << run;
  }
}

TEST(TaskThreads, TryRunRefusesWhileARunIsUnderWayAndRunsAfterIt) {
  TaskThreads threads(1);
  std::vector<int> times(3, 0);
  std::atomic<int> refused{0};
  const bool ran = threads.try_run(3, [&](std::size_t i) {
    ++times[i];
    if (!threads.try_run(1, [&](std::size_t) { ++times[i]; })) ++refused;  // nested: refused
  });
  EXPECT_TRUE(ran);
  EXPECT_EQ(refused, 3);
  for (int n : times) EXPECT_EQ(n, 1);
  EXPECT_TRUE(threads.try_run(3, [&](std::size_t i) { ++times[i]; }));
  for (int n : times) EXPECT_EQ(n, 2);
}

// in_parts (src/parallel_parts.hpp) on the process's part threads: every part once, also when
// parts call it again (the part threads are busy: new threads then) and when two callers share
// them.
TEST(InParts, EveryPartRunsOnceNestedAndFromTwoCallers) {
  const auto check = [](int seed) {
    bool ok = true;
    std::atomic<int> wrong_count{0};
    for (int round = 0; round < 100; ++round) {
      const int parts = 2 + (round + seed) % 5;
      std::vector<std::atomic<int>> outer(static_cast<std::size_t>(parts));
      std::vector<std::atomic<int>> inner(static_cast<std::size_t>(parts * 3));
      in_parts(parts, [&](int k, int count) {
        ++outer[static_cast<std::size_t>(k)];
        if (count != parts) ++wrong_count;
        in_parts(3, [&](int j, int) { ++inner[static_cast<std::size_t>(k * 3 + j)]; });
      });
      for (const auto& n : outer) ok &= n == 1;
      for (const auto& n : inner) ok &= n == 1;
    }
    return ok && wrong_count == 0;
  };
  bool first = false, second = false;
  std::thread other([&] { first = check(0); });
  second = check(1);
  other.join();
  EXPECT_TRUE(first);
  EXPECT_TRUE(second);
}

TEST(TaskThreads, HelpersAreAddedWhenARunHasMoreTasks) {
  // Four tasks that each wait for all four to start, after runs that needed fewer helpers.
  TaskThreads threads(3);
  threads.run(1, [](std::size_t) {});
  threads.run(2, [](std::size_t) {});
  std::atomic<int> started{0};
  std::vector<std::thread::id> id_of(4);
  threads.run(4, [&](std::size_t i) {
    id_of[i] = std::this_thread::get_id();
    start_and_wait_for_all(started, 4);
  });
  EXPECT_EQ(started, 4);
  EXPECT_EQ(std::set<std::thread::id>(id_of.begin(), id_of.end()).size(), 4u);
}

TEST(InParts, RunsOnKeptThreadsCallAfterCall) {
  // Two parts that each wait for the other to start run on two threads at once: the caller's and
  // a part thread, kept from call to call rather than started anew. A new thread may reuse an
  // old one's id, but its thread-locals start afresh: a kept thread's count of the parts it ran
  // goes on. With at most 63 part threads, 100 calls put a second part on one of them.
  static thread_local int parts_run_here = 0;
  int most_run_before = 0;  // by the part thread, before a call's part
  for (int call = 0; call < 100; ++call) {
    std::atomic<int> started{0};
    std::vector<int> count_of(2);
    std::vector<std::thread::id> id_of(2);
    in_parts(2, [&](int k, int) {
      const auto part = static_cast<std::size_t>(k);
      id_of[part] = std::this_thread::get_id();
      count_of[part] = parts_run_here++;
      start_and_wait_for_all(started, 2);
    });
    ASSERT_EQ(started, 2);
    for (std::size_t part = 0; part < 2; ++part)
      if (id_of[part] != std::this_thread::get_id())
        most_run_before = std::max(most_run_before, count_of[part]);
  }
  EXPECT_GT(most_run_before, 0);
}

// Exit status of `child`, or -1 when it has not ended within ten seconds (then it is killed).
int status_within_ten_seconds(pid_t child) {
  for (int k = 0; k < 1000; ++k) {
    int status = 0;
    if (waitpid(child, &status, WNOHANG) == child)
      return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  return -1;
}

TEST(TaskThreads, AForkedChildRunsTasksAndLetsGoOfItsParentsHelpers) {
#if defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "ThreadSanitizer stops a child that starts threads after a threaded fork";
#elif defined(__SANITIZE_ADDRESS__)
  // GCC 12's AddressSanitizer runtime takes none of its own locks around fork (LLVM added that in
  // its version 18), so a child starting a thread can wait for ever on one a parent thread held.
  GTEST_SKIP() << "AddressSanitizer's runtime here is not fork-safe with threads";
#else
  // Python's multiprocessing forks a process whose pipeline may have started its helpers; the
  // child has none of them. Its runs must neither wait for them nor its destructor join them.
  auto* used = new TaskThreads(1);  // NOLINT: deleted in the child, left to the parent's exit
  auto* idle = new TaskThreads(1);  // NOLINT
  std::vector<int> times(4, 0);
  used->run(4, [&](std::size_t i) { ++times[i]; });
  idle->run(4, [&](std::size_t i) { ++times[i]; });
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::vector<int> seen(8, 0);
    for (int run = 0; run < 3; ++run) used->run(8, [&](std::size_t i) { ++seen[i]; });
    bool ok = true;
    for (int n : seen) ok &= n == 3;
    delete used;  // its own helpers, started in the child, joined
    delete idle;  // the parent's, let go of
    _exit(ok ? 0 : 1);
  }
  EXPECT_EQ(status_within_ten_seconds(child), 0);
  for (int n : times) EXPECT_EQ(n, 2);
  delete used;
  delete idle;
#endif
}

}  // namespace
}  // namespace iilfm::detail
