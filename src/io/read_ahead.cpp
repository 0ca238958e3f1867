#include "iilfm/io/read_ahead.hpp"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace iilfm::io {
namespace {

class ReadAheadSource : public FrameSource {
 public:
  ReadAheadSource(std::unique_ptr<FrameSource> inner, std::size_t depth)
      : inner_(std::move(inner)),
        depth_(std::max<std::size_t>(1, depth)),
        total_(inner_->total()),
        name_(inner_->name()) {
    reader_ = std::thread([this] { read(); });
  }

  ~ReadAheadSource() override {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    room_.notify_one();
    reader_.join();
  }

  bool next(Frame& frame) override {
    std::unique_lock<std::mutex> lock(mutex_);
    arrived_.wait(lock, [&] { return !queue_.empty() || finished_; });
    if (queue_.empty()) {
      if (error_) std::rethrow_exception(error_);
      return false;
    }
    // The caller's previous frame goes back to the reader, so its buffers are filled again rather
    // than freed and allocated anew for every frame.
    std::swap(frame, queue_.front());
    spare_.push_back(std::move(queue_.front()));
    queue_.pop_front();
    lock.unlock();
    room_.notify_one();
    return true;
  }

  std::size_t total() const override { return total_; }
  const std::string& name() const override { return name_; }

 private:
  void read() {
    try {
      Frame frame;
      while (true) {
        {
          std::unique_lock<std::mutex> lock(mutex_);
          room_.wait(lock, [&] { return queue_.size() < depth_ || stopping_; });
          if (stopping_) break;
          if (!spare_.empty()) {
            frame = std::move(spare_.back());
            spare_.pop_back();
          }
        }
        if (!inner_->next(frame)) break;
        {
          const std::lock_guard<std::mutex> lock(mutex_);
          queue_.push_back(std::move(frame));
        }
        arrived_.notify_one();
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      finished_ = true;
    }
    arrived_.notify_one();
  }

  const std::unique_ptr<FrameSource> inner_;  // used by the reader thread alone once it runs
  const std::size_t depth_;
  const std::size_t total_;
  const std::string name_;
  std::mutex mutex_;
  std::condition_variable arrived_, room_;  // a frame (or the end) arrived; the queue has room
  std::deque<Frame> queue_;
  std::vector<Frame> spare_;
  std::exception_ptr error_;
  bool finished_ = false, stopping_ = false;
  std::thread reader_;  // last: started once everything it uses exists
};

}  // namespace

std::unique_ptr<FrameSource> read_ahead(std::unique_ptr<FrameSource> inner, std::size_t depth) {
  return std::make_unique<ReadAheadSource>(std::move(inner), depth);
}

}  // namespace iilfm::io
