#pragma once
// Progress of long computations (simulations, identification passes, diagnoses, sweeps), reported
// through a callback the caller supplies in the options of the computation. The library never
// prints; the command-line tools display the events on the terminal.
#include <functional>
#include <string_view>

namespace vehs {

/// `done` of `total` units of `task` ("simulate", "identify", "likelihood fit", ...) are complete;
/// `finished` on the last event of a task. total 0: a phase whose length is not known in advance
/// (done counts its steps so far). While a task runs, an event comes at least every half second (the
/// count repeated when no unit completed), so a long unit of work is never silent.
struct ProgressEvent {
  std::string_view task;
  long long done = 0;
  long long total = 0;
  bool finished = false;
  double seconds = 0.0;  ///< since the task started
};

/// Called from whichever thread completed work, never by two threads at once. Intermediate events
/// may be skipped while the callback is busy; the final one is always delivered. An empty function
/// means no reports.
using ProgressCallback = std::function<void(const ProgressEvent&)>;

}  // namespace vehs
