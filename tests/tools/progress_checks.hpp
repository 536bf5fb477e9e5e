#pragma once
// The progress contract (include/vehs/core/progress.hpp) checked on a recorded run: the last
// report comes at the end of the call, no stretch of a run is silent for long, and within a task
// the total never changes, the count never falls and `finished` only closes it.
#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace vehs_tool_test {

struct RecordedEvent {
  std::string task;
  long long done = 0, total = 0;
  bool finished = false;
  double at = 0.0;  ///< seconds since the call started, by the test's clock
};

/// Empty when the events of a call that took `wall` seconds keep the contract: the last event
/// within 5 % of the wall time of the end, no gap between events longer than `max_gap` seconds,
/// per task a constant total (never decreasing), a count that never falls, and `finished` on its
/// last event only. Else what failed, with the events around it.
inline std::string progress_problems(const std::vector<RecordedEvent>& events, double wall, double max_gap) {
  std::ostringstream why;
  if (events.empty()) return "no progress events in a call of " + std::to_string(wall) + " s";
  const double end_gap = wall - events.back().at;
  if (end_gap > 0.05 * wall) why << "the last event came " << end_gap << " s before the end of a " << wall << " s call; ";
  double previous = 0.0;
  std::string previous_task = "(start)";
  std::map<std::string, RecordedEvent> last;
  for (const RecordedEvent& e : events) {
    if (e.at - previous > max_gap)
      why << "silent for " << (e.at - previous) << " s between " << previous_task << " at " << previous << " s and "
          << e.task << " at " << e.at << " s; ";
    const auto it = last.find(e.task);
    if (it != last.end()) {
      if (it->second.finished) why << e.task << " reported after it finished; ";
      if (e.total < it->second.total) why << e.task << "'s total fell from " << it->second.total << " to " << e.total << "; ";
      if (e.done < it->second.done) why << e.task << "'s count fell from " << it->second.done << " to " << e.done << "; ";
    }
    last[e.task] = e;
    previous = e.at;
    previous_task = e.task;
  }
  return why.str();
}

}  // namespace vehs_tool_test
