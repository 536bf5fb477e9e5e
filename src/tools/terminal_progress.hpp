#pragma once
// Progress of the library's computations on stderr: "[task] done/total (pct%) elapsed s",
// rewritten in place at most every 0.5 s; a final line when the task took longer than 0.5 s.
#include "vehs/core/progress.hpp"

namespace vehs::tools {

/// A ProgressCallback printing to stderr (each call of this function gives an independent
/// display with its own throttle).
ProgressCallback terminal_progress();

}  // namespace vehs::tools
