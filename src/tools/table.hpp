#pragma once
// Numeric tables written as CSV (sweeps, figure data, study results, parameter tables). A
// non-finite value (a failed sweep point, a parameter a model lacks) is written as an empty cell.
#include <string>
#include <vector>

namespace vehs::tools {

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::string label_column;         ///< when set, a leading text column with this title
  std::vector<std::string> labels;  ///< one per row when label_column is set
  std::string text_column;          ///< when set, a trailing text column with this title
  std::vector<std::string> texts;   ///< one per row when text_column is set (add_text_row)

  explicit Table(std::vector<std::string> cols = {}, std::string label_col = "")
      : columns(std::move(cols)), label_column(std::move(label_col)) {}
  void add_row(std::vector<double> row);  ///< throws when the width differs from columns
  void add_row(std::string label, std::vector<double> row);
  /// A labelled row with its trailing text (text_column set).
  void add_text_row(std::string label, std::vector<double> row, std::string text);
  std::string to_csv(int precision = 10) const;
  /// Writes the CSV atomically.
  void write_csv(const std::string& path, int precision = 10) const;
};

}  // namespace vehs::tools
