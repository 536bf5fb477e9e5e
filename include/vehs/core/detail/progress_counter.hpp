#pragma once
// Internal: counts completed units of work in parallel loops and forwards them to a
// ProgressCallback (calls serialised; a busy callback makes the others skip their report).
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

#include "vehs/core/progress.hpp"

namespace vehs::detail {

class ProgressCounter {
 public:
  ProgressCounter(const ProgressCallback& callback, std::string task, long long total)
      : callback_(total > 0 ? &callback : nullptr), task_(std::move(task)), total_(total),
        start_(std::chrono::steady_clock::now()) {
    if (callback_ && !*callback_) callback_ = nullptr;
  }
  ~ProgressCounter() { finish(); }
  ProgressCounter(const ProgressCounter&) = delete;
  ProgressCounter& operator=(const ProgressCounter&) = delete;

  /// Adds `n` completed units (thread-safe).
  void advance(long long n = 1) {
    const long long done = done_.fetch_add(n) + n;
    if (!callback_) return;
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_) return;
    report(done, false);
  }

  /// Reports the final count (once).
  void finish() {
    if (!callback_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    finished_ = true;
    report(done_.load(), true);
  }

 private:
  void report(long long done, bool final) {
    ProgressEvent e;
    e.task = task_;
    e.done = done;
    e.total = total_;
    e.finished = final;
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    (*callback_)(e);
  }

  const ProgressCallback* callback_;
  std::string task_;
  long long total_;
  std::chrono::steady_clock::time_point start_;
  std::atomic<long long> done_{0};
  std::mutex mutex_;
  bool finished_ = false;
};

}  // namespace vehs::detail
