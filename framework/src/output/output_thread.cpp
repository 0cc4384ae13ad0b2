// OutputThread (see output_thread.hpp).
#include "output_thread.hpp"

#include <utility>

namespace scree {

OutputThread::OutputThread() : thread_([this] { loop(); }) {}

OutputThread::~OutputThread() {
  {
    std::lock_guard lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void OutputThread::submit(Job job) {
  std::unique_lock lock(m_);
  cv_.wait(lock, [this] { return jobs_.empty() || error_; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  jobs_.push_back(std::move(job));
  cv_.notify_all();
}

void OutputThread::drain() {
  std::unique_lock lock(m_);
  cv_.wait(lock, [this] { return (jobs_.empty() && !busy_) || error_; });
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void OutputThread::loop() {
  std::unique_lock lock(m_);
  for (;;) {
    cv_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
    if (jobs_.empty()) return;
    Job job = std::move(jobs_.front());
    jobs_.pop_front();
    busy_ = true;
    lock.unlock();
    try {
      job();
    } catch (...) {
      lock.lock();
      if (!error_) error_ = std::current_exception();
      busy_ = false;
      cv_.notify_all();
      continue;
    }
    lock.lock();
    busy_ = false;
    cv_.notify_all();
  }
}

}  // namespace scree
