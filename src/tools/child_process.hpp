#pragma once
// Runs an external program without a shell: the arguments go to the program as an argv vector,
// never through `sh -c`, so no text of a config, model or data file can become a command.
#include <string>
#include <vector>

namespace vehs::tools {

/// The absolute path of `program` found on the PATH (an executable regular file), or "" when absent.
std::string find_on_path(const std::string& program);

/// Runs argv[0] (searched on the PATH) with the arguments argv[1...] in folder `cwd`, its standard
/// input from /dev/null and its standard error into `stderr_file` (relative to `cwd`). The caller
/// waits; while it waits, the tools' signal handler (install_signal_cleanup) stops the child on
/// SIGINT/SIGTERM/SIGHUP before it removes the run's temporary files. Returns the exit status, or
/// -1 when the program could not be started or ended by a signal.
int run_program(const std::vector<std::string>& argv, const std::string& cwd, const std::string& stderr_file);

}  // namespace vehs::tools
