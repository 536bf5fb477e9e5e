#pragma once
// Internal: records from rows, the same for every file format. A reader hands each data row's
// values (NaN for an empty field) to RecordBuilder::row; it splits records at a new record id, a
// time gap or a missing value (or fails, ReadOptions::on_gap), checks the time steps against the
// jitter tolerance, and fills the Dataset.
#include <cstddef>
#include <set>
#include <string>
#include <string_view>

#include "vehs/core/dataset.hpp"
#include "vehs/io/measurements.hpp"

namespace vehs::io_detail {

/// Which columns a file has.
struct Columns {
  bool t = false, traj = false, u = false, y = false;
};

/// One data row: `line` is the 1-based line (CSV) or row + 1 (binary formats). `id` is the record
/// id column's value as read (RecordBuilder checks it: kMaxRecordId); `id_text` its text when the
/// format has one (CSV), for messages.
struct Row {
  std::size_t line = 0;
  double id = 0.0;
  std::string_view id_text;
  double t = 0.0, x = 0.0, u = 0.0, y = 0.0;
};

/// The largest record id magnitude, 2^53 - 1: ids pass through a double, which holds every
/// integer up to it exactly (larger ids could not be told apart).
inline constexpr double kMaxRecordId = 9007199254740991.0;

class RecordBuilder {
 public:
  RecordBuilder(Dataset& d, std::string source, const ReadOptions& o, Columns c, ReadSummary& summary,
                const char* line_word = "line");

  void row(const Row& r);
  /// Closes the last record; throws when the file gave none.
  void finish();
  /// "file: line 12 (record traj=3)".
  std::string where(std::size_t line) const;

 private:
  void start(const Row& r, long long id);
  /// The row's record id: an integer of magnitude at most kMaxRecordId, else throws naming the row.
  long long record_id(const Row& r) const;
  void close(bool split);
  void missing(const Row& r, const char* what);
  /// Throws at the second of two equal steps off the interval (both gaps, or both too short).
  void check_interval_change(const Row& r, double step);

  Dataset& d_;
  std::string source_;
  const ReadOptions& o_;
  Columns c_;
  ReadSummary& summary_;
  const char* line_word_;
  bool open_ = false, after_split_ = false, in_missing_run_ = false;
  Record cur_;
  long long last_id_ = 0;
  bool any_id_ = false;
  double last_t_ = 0.0, ref_dt_ = 0.0;
  double prev_off_step_ = 0.0;  ///< the previous step when it was off the interval (0: it was not)
  std::size_t prev_off_line_ = 0;
  double min_step_ = 0.0, max_step_ = 0.0;
  std::size_t min_line_ = 0, max_line_ = 0;
  std::set<long long> seen_;
  std::string first_problem_;  ///< the first gap or missing value, for an empty result's error
};

}  // namespace vehs::io_detail
