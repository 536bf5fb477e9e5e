#include "tools/figures.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "vehs/io/atomic_file.hpp"
#include "vehs/io/output_transaction.hpp"

namespace vehs::tools {

bool gnuplot_available() {
  static const bool available = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  return available;
}

std::string render_figure(const std::string& dir, const std::string& name, const std::string& body,
                          const std::string& format, int width, int height) {
  namespace fs = std::filesystem;
  std::error_code ec;
  OutputTransaction* transaction = OutputTransaction::active();
  if (!transaction) fs::create_directories(dir, ec);
  const std::string out = name + "." + format;
  std::ostringstream script;
  if (format == "svg")
    script << "set terminal svg size " << width << "," << height
           << " dynamic noenhanced font 'sans,12' background rgb 'white'\n";  // labels as written
  else
    script << "set terminal pngcairo size " << width << "," << height << " noenhanced font 'sans,11'\n";
  script << "set output '" << out << "'\nset datafile separator ','\n" << body << "\n";
  write_file_atomically((fs::path(dir) / (name + ".gp")).string(), script.str());
  if (!gnuplot_available()) {
    std::fprintf(stderr, "warning: gnuplot not found; wrote %s/%s.gp without rendering it\n",
                 dir.c_str(), name.c_str());
    return "";
  }
  // gnuplot writes the figure next to the script: in the staging folder inside a transaction, where
  // the script and its data files are until the run commits
  const std::string work = transaction ? transaction->staging_directory(dir) : dir;
  const std::string cmd = "cd '" + work + "' && gnuplot '" + name + ".gp' 2>'" + name + ".log'";
  if (std::system(cmd.c_str()) != 0) {
    fs::remove(fs::path(work) / out, ec);  // gnuplot leaves a partial figure behind
    if (transaction) transaction->adopt((fs::path(dir) / (name + ".log")).string());
    std::fprintf(stderr, "warning: gnuplot failed on %s/%s.gp (see %s.log)\n", dir.c_str(),
                 name.c_str(), name.c_str());
    return "";
  }
  fs::remove(fs::path(work) / (name + ".log"), ec);
  if (transaction) transaction->adopt((fs::path(dir) / out).string());
  return (fs::path(dir) / out).string();
}

}  // namespace vehs::tools
