#pragma once
// Measurement files (contracts.md §1): CSV with a header row, columns t, x and optionally
// traj (record id), u (recorded drive), y (true velocity, written by the simulator only);
// and a binary form: NumPy .npy with a structured dtype of the same named fields.
//
// All records of all files are held in one Dataset whose columns are concatenated, so memory
// is 8 bytes per sample per loaded column and nothing else grows with the data.
#include <cstddef>
#include <string>
#include <vector>

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
};

/// One independent record: a contiguous block of samples in its Dataset.
struct Record {
  std::string source;          ///< file it came from
  long long id = 0;            ///< value of the traj column (0 when the file has none)
  std::size_t first_line = 0;  ///< 1-based line of its first sample in the file (header = 1)
  double t0 = 0.0;             ///< time of the first sample
  double dt = 0.0;             ///< sampling interval (uniform, checked)
  std::size_t offset = 0;      ///< index of its first sample in the Dataset columns
  std::size_t size = 0;        ///< number of samples
};

struct Dataset {
  std::vector<Record> records;
  std::vector<double> x;  ///< all records' displacement, concatenated
  std::vector<double> u;  ///< drive, same layout, or empty when no file had one
  std::vector<double> y;  ///< true velocity when read, else empty

  bool has_u() const { return !u.empty(); }
  bool has_y() const { return !y.empty(); }
  std::size_t total_samples() const { return x.size(); }
  const double* x_of(const Record& r) const { return x.data() + r.offset; }
  const double* u_of(const Record& r) const { return u.empty() ? nullptr : u.data() + r.offset; }
  const double* y_of(const Record& r) const { return y.empty() ? nullptr : y.data() + r.offset; }
  /// Common sampling interval; throws vehs::Error naming two records that disagree by more
  /// than the jitter tolerance.
  double common_dt() const;
  /// Appends another dataset (its offsets are shifted).
  void append(Dataset&& other);
};

/// Reads one measurement file; the format is chosen by extension (.npy binary, else CSV).
/// Errors name the file, the record and the line/row.
Dataset read_measurements(const std::string& path, const ReadOptions& options = {});
/// Reads several files into one dataset (records keep their source).
Dataset read_measurements(const std::vector<std::string>& paths, const ReadOptions& options = {});

/// Subtracts each record's mean from x and u (the DC offsets of real sensors; config key
/// `detrend: "mean"`).
void subtract_record_means(Dataset& data);

/// Columns for writing; u and y may be empty.
struct WriteColumns {
  bool with_y = true;
  bool with_u = false;
  int precision = 17;  ///< significant digits of CSV numbers (17 round-trips exactly)
};

/// Writes a dataset as CSV (traj,t,x[,y][,u]) or .npy by extension, atomically.
void write_measurements(const std::string& path, const Dataset& data, const WriteColumns& cols);

}  // namespace vehs
