#include "record_builder.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"

namespace vehs::io_detail {

namespace {
constexpr double kGapSteps = 1.5;  ///< a step longer than this many intervals is a gap
std::string fmt(double v) { return vehs::detail::format_number(v, 8); }
std::string shortest(double v) {  // the digits that read back as v (0.2, 9007199254740994)
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}
}

RecordBuilder::RecordBuilder(Dataset& d, std::string source, const ReadOptions& o, Columns c,
                             ReadSummary& summary, const char* line_word)
    : d_(d), source_(std::move(source)), o_(o), c_(c), summary_(summary), line_word_(line_word) {}

std::string RecordBuilder::where(std::size_t line) const {
  std::string s = source_ + ": " + line_word_ + " " + std::to_string(line);
  if (c_.traj && open_) s += " (record traj=" + std::to_string(cur_.id) + ")";
  return s;
}

long long RecordBuilder::record_id(const Row& r) const {
  if (r.id == std::floor(r.id) && std::abs(r.id) <= kMaxRecordId) return static_cast<long long>(r.id);
  const std::string at = source_ + ": " + line_word_ + " " + std::to_string(r.line) + ": record id";
  if (std::isnan(r.id)) throw Error(at + " is empty or not a number");
  const std::string text = " " + (r.id_text.empty() ? shortest(r.id) : "'" + std::string(r.id_text) + "'");
  if (r.id != std::floor(r.id)) throw Error(at + text + " is not an integer");
  throw Error(at + text + " is beyond the largest record id, 2^53 - 1 = 9007199254740991 (ids are read as "
              "double-precision numbers, exact only up to there)");
}

void RecordBuilder::row(const Row& r) {
  const long long id = c_.traj ? record_id(r) : 0;
  if (c_.traj && any_id_ && id != last_id_) {
    prev_off_step_ = 0.0;
    close(false);
    in_missing_run_ = false;
    after_split_ = false;
  }
  if (c_.traj && (!any_id_ || id != last_id_)) {
    if (!seen_.insert(id).second)
      throw Error(source_ + ": " + line_word_ + " " + std::to_string(r.line) + ": record traj=" +
                  std::to_string(id) + " appears again after other records (rows of one record must be contiguous)");
    last_id_ = id;
    any_id_ = true;
  }
  if (!std::isfinite(r.x)) return missing(r, o_.x_column.c_str());
  if (c_.t && !std::isfinite(r.t)) return missing(r, o_.t_column.c_str());
  if (c_.u && !std::isfinite(r.u)) return missing(r, o_.u_column.c_str());
  in_missing_run_ = false;
  if (open_ && c_.t) {
    const double step = r.t - last_t_;
    if (!(step > 0.0))
      throw Error(where(r.line) + ": time " + fmt(r.t) + " does not increase (previous " +
                  fmt(last_t_) + ")");
    if (ref_dt_ == 0.0) {
      if (o_.dt > 0.0 && std::abs(step - o_.dt) > o_.jitter_tolerance * o_.dt)
        throw Error(where(r.line) + ": the time column is sampled at " + fmt(step) + " but dt = " + fmt(o_.dt) +
                    " is given (remove dt to use the time column, or resample the data)");
      ref_dt_ = o_.dt > 0.0 ? o_.dt : step;
    }
    check_interval_change(r, step);
    if (step > kGapSteps * ref_dt_) {
      if (o_.on_gap == GapPolicy::Fail)
        throw Error(where(r.line) + ": a gap in the time column: step " + fmt(step) + " after " +
                    fmt(last_t_) + " is " + fmt(step / ref_dt_) +
                    " sampling intervals (on_gap \"fail\"; \"split\" splits the record there)");
      ++summary_.gaps;
      if (first_problem_.empty())
        first_problem_ = std::string(line_word_) + " " + std::to_string(r.line) + ": a gap of " + fmt(step / ref_dt_) +
                         " sampling intervals";
      close(true);
    }
  }
  if (!open_) start(r, id);
  if (c_.t && r.line != cur_.first_line) {
    const double step = r.t - last_t_;
    if (step < min_step_ || min_line_ == 0) min_step_ = step, min_line_ = r.line;
    if (step > max_step_ || max_line_ == 0) max_step_ = step, max_line_ = r.line;
    last_t_ = r.t;
  }
  d_.x.push_back(r.x);
  if (c_.u) d_.u.push_back(r.u);
  if (c_.y) d_.y.push_back(r.y);
}

void RecordBuilder::check_interval_change(const Row& r, double step) {
  // a gap (longer than kGapSteps intervals) or a step that short and beyond the jitter tolerance
  const bool off = step > kGapSteps * ref_dt_ ||
                   (step * kGapSteps < ref_dt_ && ref_dt_ - step > o_.jitter_tolerance * ref_dt_);
  if (!off) {
    prev_off_step_ = 0.0;
    return;
  }
  // two such steps of one size in a row: the data are sampled at another interval from the first
  // of them (a record at 2 ms after records at 1 ms would otherwise be cut into single samples and
  // dropped; one at 0.5 ms would be blamed on a jittering clock at some earlier line)
  if (prev_off_step_ > 0.0 && std::abs(step - prev_off_step_) <= o_.jitter_tolerance * step)
    throw Error(where(prev_off_line_) + ": the sampling interval changes from " + fmt(ref_dt_) + " to " +
                fmt(prev_off_step_) + " (all records must share one sampling interval: resample, or fit the parts separately)");
  prev_off_step_ = step;
  prev_off_line_ = r.line;
}

void RecordBuilder::missing(const Row& r, const char* what) {
  if (o_.on_gap == GapPolicy::Fail)
    throw Error(where(r.line) + ": column '" + what +
                "' is empty, NaN or infinite (on_gap \"fail\"; \"split\" splits the record there)");
  ++summary_.missing_rows;
  if (first_problem_.empty())
    first_problem_ = std::string(line_word_) + " " + std::to_string(r.line) + ": column '" + what +
                     "' is empty, NaN or infinite";
  if (!in_missing_run_) {
    ++summary_.missing_runs;
    in_missing_run_ = true;
  }
  close(true);
}

void RecordBuilder::start(const Row& r, long long id) {
  cur_ = Record{};
  cur_.source = source_;
  cur_.id = id;
  cur_.first_line = r.line;
  cur_.offset = d_.x.size();
  cur_.t0 = c_.t ? r.t : 0.0;
  last_t_ = r.t;
  min_line_ = max_line_ = 0;
  open_ = true;
}

void RecordBuilder::close(bool split) {
  const bool piece = split || after_split_;
  after_split_ = split;
  if (!open_) return;
  open_ = false;
  cur_.size = d_.x.size() - cur_.offset;
  if (cur_.size < o_.min_samples) {
    if (!piece)
      throw Error(source_ + ": " + line_word_ + " " + std::to_string(cur_.first_line) + ": record " +
                  (c_.traj ? "traj=" + std::to_string(cur_.id) + " " : "") + "has only " +
                  std::to_string(cur_.size) + " samples (at least " + std::to_string(o_.min_samples) + " needed)");
    ++summary_.dropped_pieces;
    summary_.dropped_samples += cur_.size;
    d_.x.resize(cur_.offset);
    if (c_.u) d_.u.resize(cur_.offset);
    if (c_.y) d_.y.resize(cur_.offset);
    return;
  }
  if (!c_.t) {
    cur_.dt = o_.dt;
  } else {
    const double mean = (last_t_ - cur_.t0) / static_cast<double>(cur_.size - 1);
    const double dt = o_.dt > 0.0 ? o_.dt : mean;
    const double lo = (dt - min_step_) / dt, hi = (max_step_ - dt) / dt;
    const double jitter = std::max(lo, hi);
    if (jitter > o_.jitter_tolerance) {
      const std::size_t line = hi >= lo ? max_line_ : min_line_;
      const double step = hi >= lo ? max_step_ : min_step_;
      open_ = true;  // name the record
      const std::string w = where(line);
      open_ = false;
      throw Error(w + ": non-uniform sampling: step " + fmt(step) + " differs from the " +
                  (o_.dt > 0.0 ? "given dt " : "record's mean interval ") + fmt(dt) +
                  " by " + fmt(jitter * 100.0) + " % (relative jitter > jitter_tolerance " +
                  fmt(o_.jitter_tolerance) + ")");
    }
    // the mean of n − 1 steps, each within the tolerance, is that much closer to dt
    const double mean_tolerance = 2.0 * o_.jitter_tolerance / static_cast<double>(cur_.size - 1) + 1e-6;
    if (o_.dt > 0.0 && std::abs(mean - o_.dt) > mean_tolerance * o_.dt)
      throw Error(source_ + ": the record starting at " + line_word_ + " " + std::to_string(cur_.first_line) +
                  ": the time column's mean interval " + fmt(mean) + " disagrees with the given dt " + fmt(o_.dt) +
                  " (each step may jitter by jitter_tolerance, their mean must match dt: remove dt to use the time column)");
    summary_.max_jitter = std::max(summary_.max_jitter, jitter);
    cur_.dt = dt;
  }
  d_.records.push_back(cur_);
}

void RecordBuilder::finish() {
  close(false);
  if (d_.records.empty())
    throw Error(source_ + ": no usable data rows" +
                (first_problem_.empty()
                     ? std::string()
                     : ": " + first_problem_ + " (on_gap \"split\" splits records at gaps and missing values; " +
                           std::to_string(summary_.dropped_pieces) + " piece(s) shorter than " +
                           std::to_string(o_.min_samples) + " samples were dropped)"));
}

}  // namespace vehs::io_detail
