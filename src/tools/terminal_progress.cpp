#include "tools/terminal_progress.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include <unistd.h>

namespace vehs::tools {

namespace {

struct Display {
  using Clock = std::chrono::steady_clock;
  std::string task;
  bool terminal = isatty(fileno(stderr)) != 0;
  double interval = terminal ? 0.5 : 2.0;  ///< seconds between lines (a log gets fewer of them)
  Clock::time_point last = Clock::now();   ///< when the last line was printed (or the display made)
  bool open = false;                       ///< a terminal line of `task` without its newline yet

  void operator()(const ProgressEvent& e) {
    const bool other = e.task != task;
    if (other && open) std::fputc('\n', stderr), open = false;  // keep the last task's line
    if (other) task = std::string(e.task);
    const Clock::time_point now = Clock::now();
    if (e.finished) {
      if (e.seconds > 0.5) print(e, terminal ? "\n" : " done\n"), last = now, open = false;
      return;
    }
    // one clock over every task: a phase that starts after another still prints within `interval`
    if (std::chrono::duration<double>(now - last).count() < interval) return;
    last = now;
    print(e, terminal ? "" : "\n");
    open = terminal;
  }
  void print(const ProgressEvent& e, const char* end) const {
    const int n = static_cast<int>(e.task.size());
    if (e.total > 0)
      std::fprintf(stderr, "%s[%.*s] %lld/%lld (%.0f%%) %.1f s%s", terminal ? "\r" : "", n, e.task.data(), e.done,
                   e.total, 100.0 * static_cast<double>(e.done) / static_cast<double>(e.total), e.seconds, end);
    else  // a phase of unknown length: its steps so far
      std::fprintf(stderr, "%s[%.*s] %lld steps %.1f s%s", terminal ? "\r" : "", n, e.task.data(), e.done, e.seconds,
                   end);
    std::fflush(stderr);
  }
};

}  // namespace

ProgressCallback terminal_progress() {
  auto display = std::make_shared<Display>();
  return [display](const ProgressEvent& e) { (*display)(e); };
}

const char* stderr_line_start() {
  static const bool terminal = isatty(fileno(stderr)) != 0;
  return terminal ? "\r\033[K" : "";
}

}  // namespace vehs::tools
