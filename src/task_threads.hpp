// Threads kept for a caller's repeated lists of tasks (a pipeline's detectors frame after frame,
// the parallel passes of in_parts): started once, so a frame pays neither a thread's start nor
// its buffers' first allocation (the thread-local scratch of contour tracing, reused from the
// frame before).
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>

namespace iilfm::detail {

class TaskThreads {
 public:
  // Up to `helpers` threads besides the caller's, started as runs need them (n - 1 for a run of
  // n tasks).
  explicit TaskThreads(int helpers);
  ~TaskThreads();
  TaskThreads(const TaskThreads&) = delete;
  TaskThreads& operator=(const TaskThreads&) = delete;

  // Calls task(i) once for every i < count, on the caller's thread and the helpers, each taking
  // the next task not yet taken; returns when all are done. `task` must not throw. One run at a
  // time. In a process forked after the helpers started (Python's multiprocessing), which holds
  // none of them, new ones are started.
  void run(std::size_t count, const std::function<void(std::size_t)>& task);

  // As run, but callers on several threads may try at once: returns false at once, running
  // nothing, while another try_run is under way (another caller's, or a nested one from a task).
  // Not to be mixed with run on one object.
  bool try_run(std::size_t count, const std::function<void(std::size_t)>& task);

 private:
  struct State;
  // Starts helpers until `wanted` run (at most `helpers`), first making the state.
  void start_helpers(std::size_t wanted);
  // In a forked child, leaves the parent's helpers and their state alone (the threads do not exist
  // there; their lock may be held).
  void let_go_if_forked();

  int helpers_;
  pid_t owner_ = 0;  // the process that started the helpers
  std::unique_ptr<State> state_;
  std::atomic<bool> running_{false};  // a try_run under way
};

// The process's threads for detail::in_parts (parallel_parts.hpp): up to a helper for every core
// but one (at least one), started as calls need them.
TaskThreads& part_threads();

}  // namespace iilfm::detail
