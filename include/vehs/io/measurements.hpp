#pragma once
// Measurement files (docs/measurements.md): CSV with a header row, columns t, x and optionally
// traj (record id), u (recorded drive), y (true velocity, written by the simulator only);
// NumPy .npy with a structured dtype of the same named fields, or a 2-D float array whose
// columns ReadOptions::columns names; MATLAB .mat (v5/v7/v7.3 through libmatio): one vector per
// column, named like the CSV columns, or one 2-D matrix with ReadOptions::columns. All records
// of all files are read into one Dataset (vehs/core/dataset.hpp).
//
// CSV as data loggers write it: a UTF-8 byte-order mark, `#` comment lines (before the header
// and between rows), blank lines, `,`, `;` or tab delimiters (the most frequent of them in the
// header row), quoted names and values, trailing delimiters. Duplicate column names are an error.
//
// Time column: each record's interval is its mean step; a step may deviate from it by
// `jitter_tolerance` (relative; logged time stamps are rounded, float32 or jittered) — above
// `jitter_warning` the deviation is reported as a warning. With `dt` given the time column is
// only checked against it. A step longer than 1.5 intervals is a gap; a row whose x, t or u is
// empty, NaN or infinite is missing. Both split the record there (`on_gap` Split: the pieces
// become records of their own, pieces shorter than min_samples are dropped, all counted in
// ReadSummary) or are an error naming the line (Fail). Records of one dataset whose mean
// intervals agree within 1e-3 get their pooled interval (one clock, jittered stamps).
#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "vehs/conventions.hpp"
#include "vehs/core/dataset.hpp"

namespace vehs {

/// What happens at a time gap or a missing value (NaN, empty field).
enum class GapPolicy { Split, Fail };

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
  std::size_t min_samples = 2;     ///< shorter records are an error (dropped pieces of a split)
  double jitter_tolerance = conventions::sampling_jitter_tolerance;  ///< accepted relative deviation of a time step from the interval
  double jitter_warning = 1e-4;    ///< a warning above this relative deviation
  GapPolicy on_gap = GapPolicy::Split;
  /// Names of the columns of a 2-D .npy array or .mat matrix, in order (e.g. {"t", "x", "u"});
  /// "" skips a column.
  std::vector<std::string> columns;
  std::string mat_variable;        ///< .mat: the matrix variable read with `columns` ("": the vectors)

  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

/// What reading did to the data beyond parsing it, for the user to see.
struct ReadSummary {
  std::size_t gaps = 0;              ///< records split at a time gap
  std::size_t missing_runs = 0;      ///< runs of missing rows (NaN, empty) that split a record
  std::size_t missing_rows = 0;      ///< rows skipped as missing
  std::size_t dropped_pieces = 0;    ///< pieces of split records shorter than min_samples
  std::size_t dropped_samples = 0;   ///< samples in them
  double max_jitter = 0.0;           ///< largest relative deviation of a step from its record's interval
  std::vector<std::string> warnings; ///< one line each, naming the file

  void merge(const ReadSummary& other);
};

/// Reads one measurement file; the format is chosen by extension (.npy binary, else CSV).
/// Errors name the file, the record and the line/row.
Dataset read_measurements(const std::string& path, const ReadOptions& options = {},
                          ReadSummary* summary = nullptr);
/// Reads a measurement file's bytes from a stream (read_measurements(path) reads files through
/// it): `name` stands for the file in messages and records, its extension chooses the format
/// (.npy binary, else CSV; .mat only from a path: libmatio reads files).
Dataset read_measurements(std::istream& in, const std::string& name, const ReadOptions& options = {},
                          ReadSummary* summary = nullptr);
/// Reads several files into one dataset (records keep their source).
Dataset read_measurements(const std::vector<std::string>& paths, const ReadOptions& options = {},
                          ReadSummary* summary = nullptr);

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
