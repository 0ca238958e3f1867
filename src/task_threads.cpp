#include "task_threads.hpp"

#include <system_error>

namespace iilfm::detail {

TaskThreads::TaskThreads(int helpers) : helpers_(helpers > 0 ? helpers : 0) {}

TaskThreads::~TaskThreads() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void TaskThreads::take_tasks(std::unique_lock<std::mutex>& lock) {
  while (next_ < count_) {
    const std::size_t i = next_++;
    const std::function<void(std::size_t)>& task = *task_;
    lock.unlock();
    task(i);
    lock.lock();
    if (++finished_ == count_) done_.notify_all();
  }
}

void TaskThreads::work() {
  std::uint64_t seen = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    take_tasks(lock);
  }
}

void TaskThreads::run(std::size_t count, const std::function<void(std::size_t)>& task) {
  if (count == 0) return;
  if (threads_.empty() && helpers_ > 0) {
    try {
      for (int k = 0; k < helpers_; ++k) threads_.emplace_back([this] { work(); });
    } catch (const std::system_error&) {  // fewer helpers (or none): the caller does the rest
    }
    helpers_ = static_cast<int>(threads_.size());
  }
  std::unique_lock<std::mutex> lock(mutex_);
  task_ = &task;
  count_ = count;
  next_ = 0;
  finished_ = 0;
  ++generation_;
  if (!threads_.empty()) wake_.notify_all();
  take_tasks(lock);
  done_.wait(lock, [&] { return finished_ == count_; });
  task_ = nullptr;
}

}  // namespace iilfm::detail
