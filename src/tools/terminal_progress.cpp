#include "tools/terminal_progress.hpp"

#include <cstdio>
#include <memory>
#include <string>

namespace vehs::tools {

namespace {

struct Display {
  std::string task;
  double last = -1.0;  ///< seconds of the last line printed for `task`

  void operator()(const ProgressEvent& e) {
    if (e.task != task) {
      task = std::string(e.task);
      last = -1.0;
    }
    if (e.finished) {
      if (e.seconds > 0.5) print(e, "\n");
      return;
    }
    if (e.seconds - last < 0.5 && last >= 0.0) return;
    if (last < 0.0 && e.seconds < 0.5) return;
    last = e.seconds;
    print(e, "");
  }
  static void print(const ProgressEvent& e, const char* end) {
    std::fprintf(stderr, "\r[%.*s] %lld/%lld (%.0f%%) %.1f s%s", static_cast<int>(e.task.size()), e.task.data(),
                 e.done, e.total, 100.0 * static_cast<double>(e.done) / static_cast<double>(e.total), e.seconds,
                 end);
    std::fflush(stderr);
  }
};

}  // namespace

ProgressCallback terminal_progress() {
  auto display = std::make_shared<Display>();
  return [display](const ProgressEvent& e) { (*display)(e); };
}

}  // namespace vehs::tools
