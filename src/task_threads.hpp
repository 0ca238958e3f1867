// Threads kept for a caller's repeated lists of tasks (a pipeline's detectors, frame after frame):
// started once, so a frame pays neither a thread's start nor its buffers' first allocation (the
// thread-local scratch of contour tracing, reused from the frame before).
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <functional>
#include <memory>

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
  // time. In a process forked after the helpers started (Python's multiprocessing), which holds
  // none of them, new ones are started.
  void run(std::size_t count, const std::function<void(std::size_t)>& task);

 private:
  struct State;
  // In a forked child, leaves the parent's helpers and their state alone (the threads do not exist
  // there; their lock may be held).
  void start_helpers();
  void let_go_if_forked();

  int helpers_;
  pid_t owner_ = 0;  // the process that started the helpers
  std::unique_ptr<State> state_;
};

}  // namespace iilfm::detail
