// Threads kept for a caller's repeated lists of tasks (a pipeline's detectors, frame after frame):
// started once, so a frame pays neither a thread's start nor its buffers' first allocation (the
// thread-local scratch of contour tracing, reused from the frame before).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace iilfm::detail {

class TaskThreads {
 public:
  // `helpers` threads besides the caller's, started on the first run.
  explicit TaskThreads(int helpers);
  ~TaskThreads();
  TaskThreads(const TaskThreads&) = delete;
  TaskThreads& operator=(const TaskThreads&) = delete;

  // Calls task(i) once for every i < count, on the caller's thread and the helpers, each taking
  // the next task not yet taken; returns when all are done. `task` must not throw. One run at a
  // time.
  void run(std::size_t count, const std::function<void(std::size_t)>& task);

 private:
  void work();
  // Runs the tasks left (the lock held on entry and on return).
  void take_tasks(std::unique_lock<std::mutex>& lock);

  int helpers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::size_t count_ = 0, next_ = 0, finished_ = 0;
  std::uint64_t generation_ = 0;  // one more for every run
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace iilfm::detail
