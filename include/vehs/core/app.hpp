#pragma once
// The common front end of the executables: `tool CONFIG.json [--set key=value]... [--threads N]
// [--quiet]`, --help printing the key table, and one-line errors with a non-zero exit.
#include <functional>

#include "vehs/core/config.hpp"

namespace vehs {

struct AppOptions {
  int threads = 0;     ///< 0: all hardware threads
  bool quiet = false;  ///< no progress on stderr
};

/// Parses the command line, loads and checks the config, runs `body`. Returns the exit code:
/// 0 success, 1 a vehs::Error (bad config, data or model; printed as one line), 2 usage.
int run_app(int argc, char** argv, const ConfigSchema& schema,
            const std::function<int(Config&, const AppOptions&)>& body);

/// Threads used by parallel loops of the library (OpenMP); 0 restores the default.
void set_threads(int threads);
int max_threads();

}  // namespace vehs
