#include "vehs/core/table.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "vehs/core/config.hpp"
#include "vehs/core/error.hpp"

namespace vehs {

void Table::add_row(std::vector<double> row) {
  require(row.size() == columns.size(), "table row has " + std::to_string(row.size()) +
                                            " values for " + std::to_string(columns.size()) + " columns");
  rows.push_back(std::move(row));
}

void Table::add_row(std::string label, std::vector<double> row) {
  require(!label_column.empty(), "table has no label column");
  require(labels.size() == rows.size(), "table mixes labelled and unlabelled rows");
  add_row(std::move(row));
  labels.push_back(std::move(label));
}

std::string Table::to_csv(int precision) const {
  std::ostringstream os;
  const bool labelled = !label_column.empty();
  if (labelled) os << label_column << (columns.empty() ? "" : ",");
  for (std::size_t i = 0; i < columns.size(); ++i) os << (i ? "," : "") << columns[i];
  os << "\n" << std::setprecision(precision);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[k];
    if (labelled) os << labels[k] << (r.empty() ? "" : ",");
    for (std::size_t i = 0; i < r.size(); ++i) os << (i ? "," : "") << r[i];
    os << "\n";
  }
  return os.str();
}

void Table::write_csv(const std::string& path, int precision) const {
  write_file_atomically(path, to_csv(precision));
}

bool gnuplot_available() {
  static const bool available = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  return available;
}

std::string render_figure(const std::string& dir, const std::string& name, const std::string& body,
                          const std::string& format, int width, int height) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  const std::string out = name + "." + format;
  std::ostringstream script;
  if (format == "svg")
    script << "set terminal svg size " << width << "," << height
           << " dynamic enhanced font 'sans,12' background rgb 'white'\n";
  else
    script << "set terminal pngcairo size " << width << "," << height << " enhanced font 'sans,11'\n";
  script << "set output '" << out << "'\nset datafile separator ','\n" << body << "\n";
  write_file_atomically((fs::path(dir) / (name + ".gp")).string(), script.str());
  if (!gnuplot_available()) {
    std::fprintf(stderr, "warning: gnuplot not found; wrote %s/%s.gp without rendering it\n",
                 dir.c_str(), name.c_str());
    return "";
  }
  const std::string cmd = "cd '" + dir + "' && gnuplot '" + name + ".gp' 2>'" + name + ".log'";
  if (std::system(cmd.c_str()) != 0) {
    fs::remove(fs::path(dir) / out, ec);  // gnuplot leaves a partial figure behind
    std::fprintf(stderr, "warning: gnuplot failed on %s/%s.gp (see %s.log)\n", dir.c_str(),
                 name.c_str(), name.c_str());
    return "";
  }
  fs::remove(fs::path(dir) / (name + ".log"), ec);
  return (fs::path(dir) / out).string();
}

}  // namespace vehs
