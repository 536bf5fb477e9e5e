#pragma once
// Progress of the library's computations on stderr: "[task] done/total (pct%) elapsed s" ("[task]
// N steps elapsed s" for a phase of unknown length),
// rewritten in place at most every 0.5 s on a terminal, one line every 2 s otherwise (a log); a
// final line when the task took longer than 0.5 s.
#include "vehs/core/progress.hpp"

namespace vehs::tools {

/// A ProgressCallback printing to stderr (each call of this function gives an independent
/// display with its own throttle).
ProgressCallback terminal_progress();

}  // namespace vehs::tools
