#include "tools/figures.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "tools/child_process.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/output_transaction.hpp"

namespace vehs::tools {

bool gnuplot_available() {
  static const bool available = !find_on_path("gnuplot").empty();
  return available;
}

std::string gnuplot_quote(std::string_view text) {
  std::string quoted = "'";
  for (const char c : text) {
    if (c == '\'')
      quoted += "''";  // the one escape of a single-quoted gnuplot string
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      quoted += ' ';  // a newline would end the command and start another
    else
      quoted += c;
  }
  return quoted + "'";
}

namespace {

/// Registers `paths` (files gnuplot writes) as temporaries of the signal handler while it runs.
struct TemporaryFiles {
  std::vector<int> slots;
  explicit TemporaryFiles(std::initializer_list<std::string> paths) {
    for (const auto& p : paths) slots.push_back(register_temporary(p, false));
  }
  ~TemporaryFiles() {
    for (const int s : slots) unregister_temporary(s);
  }
};

std::string script_text(const std::string& out, const std::string& body, const std::string& format, int width,
                        int height) {
  std::ostringstream script;
  if (format == "svg")
    script << "set terminal svg size " << width << "," << height
           << " dynamic noenhanced font 'sans,12' background rgb 'white'\n";  // labels as written
  else
    script << "set terminal pngcairo size " << width << "," << height << " noenhanced font 'sans,11'\n";
  script << "set output " << gnuplot_quote(out) << "\nset datafile separator ','\n" << body << "\n";
  return script.str();
}

}  // namespace

std::string render_figure(const std::string& dir, const std::string& name, const std::string& body,
                          const std::string& format, int width, int height) {
  namespace fs = std::filesystem;
  std::error_code ec;
  OutputTransaction* transaction = OutputTransaction::active();
  if (!transaction) fs::create_directories(dir, ec);
  const std::string out = name + "." + format, log = name + ".log";
  write_file_atomically((fs::path(dir) / (name + ".gp")).string(), script_text(out, body, format, width, height));
  if (!gnuplot_available()) {
    std::fprintf(stderr, "warning: gnuplot not found; wrote %s/%s.gp without rendering it\n",
                 dir.c_str(), name.c_str());
    return "";
  }
  // gnuplot writes the figure next to the script: in the staging folder inside a transaction, where
  // the script and its data files are until the run commits. No shell: the folder and the script's
  // name go to gnuplot as arguments.
  const std::string work = transaction ? transaction->staging_directory(dir) : dir;
  int status = -1;
  {
    const TemporaryFiles running{(fs::path(work) / out).string(), (fs::path(work) / log).string()};
    status = run_program({"gnuplot", name + ".gp"}, work, log);
  }
  if (status != 0) {
    fs::remove(fs::path(work) / out, ec);  // gnuplot leaves a partial figure behind
    if (transaction) transaction->adopt((fs::path(dir) / log).string());
    std::fprintf(stderr, "warning: gnuplot failed on %s/%s.gp (see %s)\n", dir.c_str(), name.c_str(), log.c_str());
    return "";
  }
  fs::remove(fs::path(work) / log, ec);
  if (transaction) transaction->adopt((fs::path(dir) / out).string());
  return (fs::path(dir) / out).string();
}

}  // namespace vehs::tools
