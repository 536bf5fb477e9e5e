#pragma once
// Internal: one reader per file format, each feeding io_detail::RecordBuilder.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "record_builder.hpp"

#include "vehs/core/dataset.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"

namespace vehs::io_detail {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

/// Opens a measurement file for binary reading; throws vehs::Error naming it.
inline File open_measurement_file(const std::string& path) {
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) throw Error(path + ": cannot open measurement file");
  return f;
}

Dataset read_csv(const std::string& path, const ReadOptions& o, ReadSummary& summary);
Dataset read_npy(const std::string& path, const ReadOptions& o, ReadSummary& summary);
Dataset read_mat(const std::string& path, const ReadOptions& o, ReadSummary& summary);

/// The column roles of a file from its column names (a CSV header, a structured dtype, .mat
/// variables or ReadOptions::columns): index per role, −1 when absent. Throws vehs::Error naming
/// `path` for a duplicate name, a missing x or time column, or a missing required drive.
struct ColumnIndex {
  int t = -1, x = -1, traj = -1, u = -1, y = -1;
  Columns present() const { return Columns{t >= 0, traj >= 0, u >= 0, y >= 0}; }
};
ColumnIndex index_columns(const std::vector<std::string>& names, const ReadOptions& o, const std::string& path,
                          const char* kind);

}  // namespace vehs::io_detail
