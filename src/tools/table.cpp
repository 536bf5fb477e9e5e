#include "tools/table.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "vehs/io/atomic_file.hpp"
#include "vehs/core/error.hpp"

namespace vehs::tools {

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

void Table::add_text_row(std::string label, std::vector<double> row, std::string text) {
  require(!text_column.empty(), "table has no text column");
  require(texts.size() == rows.size(), "table mixes rows with and without text");
  add_row(std::move(label), std::move(row));
  texts.push_back(std::move(text));
}

std::string Table::to_csv(int precision) const {
  std::ostringstream os;
  const bool labelled = !label_column.empty();
  if (labelled) os << label_column << (columns.empty() ? "" : ",");
  for (std::size_t i = 0; i < columns.size(); ++i) os << (i ? "," : "") << columns[i];
  if (!text_column.empty()) os << "," << text_column;
  os << "\n" << std::setprecision(precision);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[k];
    if (labelled) os << labels[k] << (r.empty() ? "" : ",");
    for (std::size_t i = 0; i < r.size(); ++i) {
      if (i) os << ',';
      if (std::isfinite(r[i])) os << r[i];  // a missing value is an empty cell, never "nan"
    }
    if (!text_column.empty()) os << "," << texts[k];
    os << "\n";
  }
  return os.str();
}

void Table::write_csv(const std::string& path, int precision) const {
  write_file_atomically(path, to_csv(precision));
}

}  // namespace vehs::tools
