#pragma once
// The common front end of the executables: `tool CONFIG.json [--set key=value]... [--threads N]
// [--quiet]`, --help printing the key table, --version, one-line errors with a non-zero exit, and
// progress on stderr (a line redrawn in place on a terminal, one line per update otherwise).
#include <functional>
#include <string>

#include "tools/config.hpp"
#include "vehs/core/progress.hpp"

namespace vehs::tools {

struct AppOptions {
  int threads = 0;     ///< 0: all hardware threads
  bool quiet = false;  ///< no progress on stderr
  /// Progress display on stderr (empty when quiet): pass it to the library's options.
  ProgressCallback progress;
};

/// "vehs 0.1.0": the version every tool prints with --version and writes into its outputs.
const char* library_version();

/// An option that names the config through another file, given instead of CONFIG
/// (`identify-vehs --refit FILE`): `resolve` maps FILE to the config's path or throws vehs::Error.
struct ConfigOption {
  std::string flag;  ///< "--refit"
  std::string help;  ///< its --help text
  std::function<std::string(const std::string&)> resolve;
};

/// Parses the command line, loads and checks the config, runs `body`. Returns the exit code:
/// 0 success, 1 a vehs::Error (bad config, data or model; printed as one line), 2 usage.
/// With `config_option`, CONFIG may be replaced by that option (one of the two is required).
int run_app(int argc, char** argv, const ConfigSchema& schema,
            const std::function<int(Config&, const AppOptions&)>& body,
            const ConfigOption* config_option = nullptr);

}  // namespace vehs::tools
