// OutputThread: runs writers and function objects on a thread of their own, one snapshot
// at a time, so that the time loop waits for a snapshot's copy, never for its files.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace scree {

class OutputThread {
 public:
  using Job = std::function<void()>;
  OutputThread();
  ~OutputThread();  ///< finishes the queued jobs, then joins
  /// Queue a job; waits while one job is already waiting (bounded memory). Rethrows the
  /// first error of an earlier job.
  void submit(Job job);
  /// Wait until the queue is empty; rethrow the first error of a job.
  void drain();

 private:
  void loop();
  std::mutex m_;
  std::condition_variable cv_;
  std::deque<Job> jobs_;
  bool stop_ = false, busy_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace scree
