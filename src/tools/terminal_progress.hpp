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

/// What a line written to stderr between progress reports starts with: on a terminal, a return
/// and a clear of the line (a progress line redrawn in place is open there), else nothing.
const char* stderr_line_start();

}  // namespace vehs::tools
