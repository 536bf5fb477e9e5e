#pragma once
// Internal: counts completed units of work in parallel loops and forwards them to a
// ProgressCallback. Calls are serialised across every counter of the process (nested phases never
// call the callback at once); a busy callback makes the others skip their intermediate report.
// While a counter with a callback lives, a heartbeat re-reports its count every half second, so that a
// phase whose units take long still says twice a second that it is working and for how long.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "vehs/core/progress.hpp"

namespace vehs::detail {

/// The lock every counter holds while it calls its callback.
inline std::mutex& progress_call_mutex() {
  static std::mutex m;
  return m;
}

class ProgressCounter {
 public:
  /// Seconds between the heartbeat's reports.
  static constexpr double kHeartbeatSeconds = 0.5;

  /// `total` units of `task`; total 0 reports nothing unless `open_ended` (a phase whose length is
  /// not known in advance: its events carry total 0 and the units done so far).
  ProgressCounter(const ProgressCallback& callback, std::string task, long long total, bool open_ended = false)
      : callback_(total > 0 || open_ended ? &callback : nullptr), task_(std::move(task)), total_(total),
        start_(std::chrono::steady_clock::now()) {
    if (callback_ && !*callback_) callback_ = nullptr;
    if (callback_) heartbeat_ = std::thread([this] { beat(); });
  }
  ~ProgressCounter() { finish(); }
  ProgressCounter(const ProgressCounter&) = delete;
  ProgressCounter& operator=(const ProgressCounter&) = delete;

  /// Adds `n` completed units (thread-safe).
  void advance(long long n = 1) {
    const long long done = done_.fetch_add(n) + n;
    if (!callback_) return;
    std::unique_lock<std::mutex> lock(progress_call_mutex(), std::try_to_lock);
    if (!lock.owns_lock() || finished_) return;
    report(done, false);
  }

  /// Reports the final count (once).
  void finish() {
    if (!callback_) return;
    stop_heartbeat();
    std::lock_guard<std::mutex> lock(progress_call_mutex());
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

  void beat() {
    std::unique_lock<std::mutex> wait(beat_mutex_);
    const auto period = std::chrono::duration<double>(kHeartbeatSeconds);
    while (!beat_cv_.wait_for(wait, period, [this] { return stop_; })) {
      wait.unlock();
      {
        std::lock_guard<std::mutex> lock(progress_call_mutex());
        try {
          if (!finished_) report(done_.load(), false);
        } catch (...) {
          // a callback that throws (an interrupted Python call) stops the work from its own
          // thread's next report; the heartbeat only stops reporting
        }
      }
      wait.lock();
    }
  }

  void stop_heartbeat() {
    if (!heartbeat_.joinable()) return;
    {
      std::lock_guard<std::mutex> lock(beat_mutex_);
      stop_ = true;
    }
    beat_cv_.notify_all();
    heartbeat_.join();
  }

  const ProgressCallback* callback_;
  std::string task_;
  long long total_;
  std::chrono::steady_clock::time_point start_;
  std::atomic<long long> done_{0};
  bool finished_ = false;  ///< guarded by progress_call_mutex()
  std::mutex beat_mutex_;
  std::condition_variable beat_cv_;
  bool stop_ = false;
  std::thread heartbeat_;
};

}  // namespace vehs::detail
