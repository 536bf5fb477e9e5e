#include "tools/app.hpp"

#include <algorithm>
#include <csignal>
#include <exception>
#include <iostream>
#include <new>

#include <CLI/CLI.hpp>

#include "tools/catalogue_markdown.hpp"
#include "tools/run_files.hpp"
#include "tools/terminal_progress.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/io/output_transaction.hpp"

namespace vehs::tools {

namespace {
constexpr long long kMaxThreads = 1024;
}  // namespace

const char* library_version() { return "vehs " VEHS_VERSION; }

int run_app(int argc, char** argv, const ConfigSchema& schema,
            const std::function<int(Config&, const AppOptions&)>& body, const ConfigOption* config_option) {
  CLI::App app{schema.summary, schema.tool};
  std::string config_path, option_file;
  std::vector<std::string> overrides;
  AppOptions options;
  CLI::Option* positional = app.add_option("config", config_path, "JSON config file (keys below)");
  if (config_option)
    positional->excludes(app.add_option(config_option->flag, option_file, config_option->help));
  else
    positional->required();
  app.add_option("--set", overrides, "override a config key: --set key=value (value is JSON)");
  app.add_option("--threads", options.threads, "threads for parallel work (default: all cores)")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            std::size_t used = 0;
            long long n = -1;
            try {
              n = std::stoll(s, &used);
            } catch (const std::exception&) {
            }
            if (used != s.size() || n < 0 || n > kMaxThreads)
              return "--threads must be 0 (all cores) or a number of threads from 1 to " +
                     std::to_string(kMaxThreads) + " (got '" + s + "')";
            return "";
          },
          "INT in [0, 1024]"));
  app.add_flag("--quiet,-q", options.quiet, "no progress reports on stderr");
  app.set_version_flag("--version", schema.tool + " (" + library_version() + ")");
  app.add_flag_callback(
         "--help-markdown",
         [&schema] {
           std::cout << schema.markdown_text();
           throw CLI::Success();
         },
         "print the config keys as Markdown (docs/reference/) and exit")
      ->trigger_on_parse();
  app.add_flag_callback(
         "--catalogue-markdown",
         [] {
           std::cout << catalogue_markdown();
           throw CLI::Success();
         },
         "print the effect catalogue as Markdown (docs/reference/effects.md) and exit")
      ->trigger_on_parse();
  // a boolean key fail_on_<x> is also the flag --fail-on-<x>, and the key force the flag --force
  std::vector<std::string> flag_keys;
  for (const auto& k : schema.keys)
    if (k.name.rfind("fail_on_", 0) == 0 || k.name == "force") flag_keys.push_back(k.name);
  std::vector<char> flag_set(flag_keys.size(), 0);  // (vector<bool> has no element references)
  for (std::size_t i = 0; i < flag_keys.size(); ++i) {
    std::string flag = "--" + flag_keys[i];
    std::replace(flag.begin(), flag.end(), '_', '-');
    app.add_flag_callback(flag, [&flag_set, i] { flag_set[i] = 1; }, "sets the config key " + flag_keys[i] + " (see below)");
  }
  app.footer(schema.help_text());
  app.get_formatter()->column_width(28);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << schema.tool << ": " << e.what() << " (see --help)\n";
    return 2;
  }
  if (config_option && config_path.empty() && option_file.empty()) {
    std::cerr << schema.tool << ": config or " << config_option->flag << " is required (see --help)\n";
    return 2;
  }
  if (!options.quiet) options.progress = terminal_progress();
  install_signal_cleanup(schema.tool.c_str());
  // a reader that stops early (tool ... | head -1) makes writes to stdout fail with EPIPE
  // instead of killing the tool: its files are still written and it exits normally
  std::signal(SIGPIPE, SIG_IGN);
  try {
    set_threads(options.threads);
    if (!option_file.empty()) config_path = config_option->resolve(option_file);
    Config config = Config::load(config_path, schema);
    for (const auto& o : overrides) config.set_override(o, schema);
    for (std::size_t i = 0; i < flag_keys.size(); ++i)
      if (flag_set[i]) config.set_override(flag_keys[i] + "=true", schema);
    // all outputs of the run or none: staged next to their destinations, moved into place at the end
    OutputTransaction outputs;
    declare_run_files(config, outputs);
    const int status = body(config, options);
    outputs.commit();  // a body that returns normally wrote a complete run (3: an inadequate verdict)
    return status;
  } catch (const Error& e) {
    std::cerr << schema.tool << ": error: " << e.what() << "\n";
  } catch (const nlohmann::json::exception& e) {
    std::cerr << schema.tool << ": error: " << config_path << ": " << e.what() << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << schema.tool << ": error: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << schema.tool << ": internal error: " << e.what() << "\n";
  }
  return 1;
}

}  // namespace vehs::tools
