#pragma once
// Displacement records in memory: every record of every source in one Dataset whose columns are
// concatenated, so memory is 8 bytes per sample per loaded column and nothing else grows with
// the data. Files are read and written by vehs/io/measurements.hpp; the simulator fills Datasets
// directly. A column may also view memory it does not own (vehs/core/column.hpp: a NumPy array
// from Python, read in place); such a Dataset is read-only until its columns are copied (own()).
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "vehs/core/column.hpp"

namespace vehs {

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
  Column x;  ///< all records' displacement, concatenated
  Column u;  ///< drive, same layout, or empty when no file had one
  Column y;  ///< true velocity when read, else empty

  bool has_u() const { return !u.empty(); }
  bool has_y() const { return !y.empty(); }
  std::size_t total_samples() const { return x.size(); }
  const double* x_of(const Record& r) const { return x.data() + r.offset; }
  const double* u_of(const Record& r) const { return u.empty() ? nullptr : u.data() + r.offset; }
  const double* y_of(const Record& r) const { return y.empty() ? nullptr : y.data() + r.offset; }
  /// Common sampling interval; throws vehs::Error naming two records that disagree by more
  /// than the jitter tolerance.
  double common_dt() const;
  /// Appends another dataset (its offsets are shifted). This dataset must own its columns
  /// (a view throws vehs::Error); `other` may view.
  void append(Dataset&& other);
  /// Copies every column that views caller memory into owned memory (nothing when none does).
  void own();
};

/// The variance of x about each record's own mean, pooled over the records (divisor: samples − 1);
/// NaN with fewer than 2 samples.
double pooled_record_variance(const Dataset& data);

/// "file: record traj=3 (from line 12)": how every error names a record.
std::string record_name(const Record& record);

/// What check_records requires of every record.
struct RecordChecks {
  std::size_t min_samples = 2;     ///< shorter records are an error
  bool positive_dt = true;         ///< a finite sampling interval > 0
  bool varying_x = false;          ///< x must not be constant
  double expected_dt = 0.0;        ///< > 0: every record must be sampled at this interval
};

/// Checks every record (in parallel): length, sampling interval, finite x and u, and what
/// `checks` asks for. Throws vehs::Error naming the first bad record and, for a bad value, the
/// sample and its line in the file.
void check_records(const Dataset& data, const RecordChecks& checks);

/// Subtracts each record's mean from x and u (the DC offsets of real sensors; config key
/// `detrend: "mean"`). Columns that view caller memory are copied first (copy-on-write: the
/// caller's array is never modified).
void subtract_record_means(Dataset& data);

/// Returned by a `take` function of leading_samples to end the selection.
inline constexpr std::size_t kEndSelection = static_cast<std::size_t>(-1);

/// A new Dataset (x and u; y is not copied) holding the first `take(i, record, samples so far)`
/// samples of records i = 0, 1, … (clipped to the record's size), until `take` returns
/// kEndSelection. Records keep their source, id, first line, t0 and dt.
Dataset leading_samples(const Dataset& data,
                        const std::function<std::size_t(std::size_t, const Record&, std::size_t)>& take);

}  // namespace vehs
