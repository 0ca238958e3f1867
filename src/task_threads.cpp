#include "task_threads.hpp"

#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace iilfm::detail {

// What the helpers share with the caller, behind one pointer so that a forked child can leave the
// parent's (its lock may have been held by a helper at the fork) and make its own.
struct TaskThreads::State {
  std::mutex mutex;
  std::condition_variable wake, done;
  const std::function<void(std::size_t)>* task = nullptr;
  std::size_t count = 0, next = 0, finished = 0;
  std::uint64_t generation = 0;  // one more for every run
  bool stop = false;
  std::vector<std::thread> threads;

  // Runs the tasks left (the lock held on entry and on return).
  void take_tasks(std::unique_lock<std::mutex>& lock) {
    while (next < count) {
      const std::size_t i = next++;
      const std::function<void(std::size_t)>& run_task = *task;
      lock.unlock();
      run_task(i);
      lock.lock();
      if (++finished == count) done.notify_all();
    }
  }

  void work() {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      wake.wait(lock, [&] { return stop || generation != seen; });
      if (stop) return;
      seen = generation;
      take_tasks(lock);
    }
  }
};

TaskThreads::TaskThreads(int helpers) : helpers_(helpers > 0 ? helpers : 0) {}

TaskThreads::~TaskThreads() {
  if (!state_) return;
  let_go_if_forked();
  if (!state_) return;
  {
    const std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stop = true;
  }
  state_->wake.notify_all();
  for (std::thread& t : state_->threads) t.join();
}

void TaskThreads::let_go_if_forked() {
  if (!state_ || owner_ == getpid()) return;
  // A forked child: the helpers were not copied, and their handles name nothing here (glibc may
  // even hand their stacks to the child's new threads), so neither joined nor detached: the state,
  // threads and lock, is left as it is (leaked), and a new one made on the next run.
  static_cast<void>(state_.release());
}

void TaskThreads::start_helpers(std::size_t wanted) {
  if (!state_) {
    state_ = std::make_unique<State>();
    owner_ = getpid();
  }
  State* const state = state_.get();
  const auto most = std::min(wanted, static_cast<std::size_t>(helpers_));
  try {
    while (state->threads.size() < most) state->threads.emplace_back([state] { state->work(); });
  } catch (const std::system_error&) {  // fewer helpers (or none): the caller does the rest
    helpers_ = static_cast<int>(state->threads.size());
  }
}

void TaskThreads::run(std::size_t count, const std::function<void(std::size_t)>& task) {
  if (count == 0) return;
  let_go_if_forked();
  start_helpers(count - 1);
  State& s = *state_;
  std::unique_lock<std::mutex> lock(s.mutex);
  s.task = &task;
  s.count = count;
  s.next = 0;
  s.finished = 0;
  ++s.generation;
  if (!s.threads.empty()) s.wake.notify_all();
  s.take_tasks(lock);
  s.done.wait(lock, [&] { return s.finished == s.count; });
  s.task = nullptr;
}

bool TaskThreads::try_run(std::size_t count, const std::function<void(std::size_t)>& task) {
  if (running_.exchange(true, std::memory_order_acquire)) return false;
  run(count, task);
  running_.store(false, std::memory_order_release);
  return true;
}

TaskThreads& part_threads() {
  static TaskThreads threads(
      std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1));
  return threads;
}

}  // namespace iilfm::detail
