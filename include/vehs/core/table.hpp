#pragma once
// Numeric tables written as CSV (sweeps, figure data, study results), and gnuplot figures
// written next to their data so users can restyle them.
#include <string>
#include <vector>

namespace vehs {

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::string label_column;         ///< when set, a leading text column with this title
  std::vector<std::string> labels;  ///< one per row when label_column is set

  explicit Table(std::vector<std::string> cols = {}, std::string label_col = "")
      : columns(std::move(cols)), label_column(std::move(label_col)) {}
  void add_row(std::vector<double> row);  ///< throws when the width differs from columns
  void add_row(std::string label, std::vector<double> row);
  std::string to_csv(int precision = 10) const;
  /// Writes the CSV atomically.
  void write_csv(const std::string& path, int precision = 10) const;
};

/// Writes `<dir>/<name>.gp` (the terminal/output lines followed by `body`) and runs gnuplot in
/// `dir` to produce `<dir>/<name>.<format>` (format "svg" or "png"). The script refers to its
/// data files by names relative to `dir`. Returns the figure's path, or an empty string (with a
/// warning on stderr) when gnuplot is missing or fails; the script is kept either way.
std::string render_figure(const std::string& dir, const std::string& name, const std::string& body,
                          const std::string& format = "svg", int width = 800, int height = 560);

/// True when a gnuplot executable is on the PATH.
bool gnuplot_available();

}  // namespace vehs
