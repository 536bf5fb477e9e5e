#pragma once
// Progress reports on stderr for long runs: throttled, thread-safe, silent when quiet.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace vehs {

class Progress {
 public:
  /// `label` e.g. "simulate"; `total` units of work (records, grid points...).
  Progress(std::string label, long long total, bool enabled = true)
      : label_(std::move(label)), total_(total), enabled_(enabled && total > 0),
        start_(std::chrono::steady_clock::now()), last_(start_) {}
  ~Progress() { finish(); }

  /// Adds `n` completed units; prints at most every 0.5 s.
  void advance(long long n = 1) {
    const long long done = done_.fetch_add(n) + n;
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || now - last_ < std::chrono::milliseconds(500)) return;
    last_ = now;
    print(done, now, false);
  }

  void finish() {
    if (!enabled_ || finished_) return;
    finished_ = true;
    const auto now = std::chrono::steady_clock::now();
    if (now - start_ > std::chrono::milliseconds(500)) print(done_.load(), now, true);
  }

  double elapsed_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  void print(long long done, std::chrono::steady_clock::time_point now, bool final) {
    const double s = std::chrono::duration<double>(now - start_).count();
    std::fprintf(stderr, "\r[%s] %lld/%lld (%.0f%%) %.1f s%s", label_.c_str(), done, total_,
                 100.0 * static_cast<double>(done) / static_cast<double>(total_), s,
                 final ? "\n" : "");
    std::fflush(stderr);
  }

  std::string label_;
  long long total_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<long long> done_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace vehs
