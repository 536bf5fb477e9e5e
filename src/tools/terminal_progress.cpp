#include "tools/terminal_progress.hpp"

#include <cstdio>
#include <memory>
#include <string>

#include <unistd.h>

namespace vehs::tools {

namespace {

struct Display {
  std::string task;
  double last = -1.0;  ///< seconds of the last line printed for `task`
  bool terminal = isatty(fileno(stderr)) != 0;
  double interval = terminal ? 0.5 : 5.0;  ///< seconds between updates (a log gets fewer lines)

  void operator()(const ProgressEvent& e) {
    if (e.task != task) {
      task = std::string(e.task);
      last = -1.0;
    }
    if (e.finished) {
      if (e.seconds > 0.5) print(e, terminal ? "\n" : " done\n");
      return;
    }
    if (e.seconds - last < interval && last >= 0.0) return;
    if (last < 0.0 && e.seconds < interval) return;
    last = e.seconds;
    print(e, terminal ? "" : "\n");
  }
  void print(const ProgressEvent& e, const char* end) const {
    std::fprintf(stderr, "%s[%.*s] %lld/%lld (%.0f%%) %.1f s%s", terminal ? "\r" : "",
                 static_cast<int>(e.task.size()), e.task.data(), e.done, e.total,
                 100.0 * static_cast<double>(e.done) / static_cast<double>(e.total), e.seconds, end);
    std::fflush(stderr);
  }
};

}  // namespace

ProgressCallback terminal_progress() {
  auto display = std::make_shared<Display>();
  return [display](const ProgressEvent& e) { (*display)(e); };
}

}  // namespace vehs::tools
