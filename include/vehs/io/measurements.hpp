#pragma once
// Measurement files (docs/measurements.md): CSV with a header row, columns t, x and optionally
// traj (record id), u (recorded drive), y (true velocity, written by the simulator only);
// and a binary form: NumPy .npy with a structured dtype of the same named fields. All records of
// all files are read into one Dataset (vehs/core/dataset.hpp).
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"

namespace vehs {

struct ReadOptions {
  std::string x_column = "x";
  std::string t_column = "t";      ///< may be absent from a file when `dt` > 0
  std::string traj_column = "traj";
  std::string u_column = "u";      ///< read when present (or required, see below)
  std::string y_column = "y";      ///< read only when `read_y`
  double dt = 0.0;                 ///< sampling interval for files without a time column
  bool require_u = false;          ///< error when a file lacks the drive column
  bool read_u = true;              ///< false: ignore a drive column even when present
  bool read_y = false;             ///< read the true velocity when present
  std::size_t min_samples = 2;     ///< shorter records are an error

  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

/// Reads one measurement file; the format is chosen by extension (.npy binary, else CSV).
/// Errors name the file, the record and the line/row.
Dataset read_measurements(const std::string& path, const ReadOptions& options = {});
/// Reads several files into one dataset (records keep their source).
Dataset read_measurements(const std::vector<std::string>& paths, const ReadOptions& options = {});

/// Columns for writing; u and y may be empty.
struct WriteColumns {
  bool with_y = true;
  bool with_u = false;
  int precision = 17;  ///< significant digits of CSV numbers (17 round-trips exactly)

  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

/// Writes a dataset as CSV (traj,t,x[,y][,u]) or .npy by extension, atomically.
void write_measurements(const std::string& path, const Dataset& data, const WriteColumns& cols);

}  // namespace vehs
