#include "vehs/core/dataset.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "vehs/conventions.hpp"
#include "vehs/core/error.hpp"

namespace vehs {

namespace {

std::string num(double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string short_num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

/// The problem of one record, or an empty string.
std::string record_problem(const Dataset& d, const Record& r, const RecordChecks& c) {
  if (r.size < c.min_samples)
    return record_name(r) + " has only " + std::to_string(r.size) + " samples (at least " +
           std::to_string(c.min_samples) + " needed)";
  if (c.positive_dt && (!(r.dt > 0.0) || !std::isfinite(r.dt)))
    return record_name(r) + " has no valid sampling interval (dt = " + short_num(r.dt) + ")";
  if (c.expected_dt > 0.0 && std::abs(r.dt - c.expected_dt) > conventions::record_dt_tolerance * c.expected_dt)
    return record_name(r) + " is sampled at dt = " + num(r.dt) + " but the config says dt = " +
           num(c.expected_dt) +
           " (remove 'dt' to use the files' time column, or give the right interval)";
  const double* x = d.x_of(r);
  const double* u = d.u_of(r);
  double lo = r.size > 0 ? x[0] : 0.0, hi = lo;
  for (std::size_t i = 0; i < r.size; ++i) {
    if (!std::isfinite(x[i]) || (u && !std::isfinite(u[i])))
      return record_name(r) + ", sample " + std::to_string(i) +
             (r.first_line > 0 ? " (line " + std::to_string(r.first_line + i) + ")" : "") + ": " +
             (std::isfinite(x[i]) ? "u" : "x") + " is NaN or infinite";
    lo = std::min(lo, x[i]);
    hi = std::max(hi, x[i]);
  }
  if (c.varying_x && !(hi > lo)) return record_name(r) + ": x is constant (" + short_num(lo) + ")";
  return "";
}

}  // namespace

double Dataset::common_dt() const {
  require(!records.empty(), "dataset has no records");
  const double dt = records.front().dt;
  for (const auto& r : records)
    if (std::abs(r.dt - dt) > conventions::record_dt_tolerance * dt)
      throw Error(r.source + ": record " + std::to_string(r.id) + " has dt = " + num(r.dt) + " but " +
                  records.front().source + " record " + std::to_string(records.front().id) +
                  " has dt = " + num(dt) + " (all records must share one sampling interval)");
  return dt;
}

void Dataset::append(Dataset&& other) {
  const std::size_t shift = x.size();
  if (has_u() != other.has_u() && !records.empty())
    throw Error(other.records.front().source + ": has " + (other.has_u() ? "a" : "no") +
                " drive column u, unlike " + records.front().source);
  if (has_y() != other.has_y() && !records.empty()) {
    y.clear();
    other.y.clear();
  }
  for (auto& r : other.records) {
    r.offset += shift;
    records.push_back(std::move(r));
  }
  const Dataset& from = other;  // read only: `other` may view caller memory
  x.insert(x.end(), from.x.begin(), from.x.end());
  u.insert(u.end(), from.u.begin(), from.u.end());
  y.insert(y.end(), from.y.begin(), from.y.end());
}

void Dataset::own() {
  x.own();
  u.own();
  y.own();
}

std::string record_name(const Record& r) {
  std::string s = r.source.empty() ? "data" : r.source;
  s += ": record traj=" + std::to_string(r.id);
  if (r.first_line > 0) s += " (from line " + std::to_string(r.first_line) + ")";
  return s;
}

void check_records(const Dataset& data, const RecordChecks& checks) {
  require(!data.records.empty(), "no records");
  std::vector<std::string> problems(data.records.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (long ri = 0; ri < static_cast<long>(data.records.size()); ++ri) {
    const auto r = static_cast<std::size_t>(ri);
    problems[r] = record_problem(data, data.records[r], checks);
  }
  for (const auto& p : problems)
    if (!p.empty()) throw Error(p);
}

void subtract_record_means(Dataset& data) {
  data.x.own();
  data.u.own();
  for (const auto& r : data.records) {
    auto center = [&](Column& col) {
      if (col.empty()) return;
      double m = 0.0;
      for (std::size_t i = 0; i < r.size; ++i) m += col[r.offset + i];
      m /= static_cast<double>(r.size);
      for (std::size_t i = 0; i < r.size; ++i) col[r.offset + i] -= m;
    };
    center(data.x);
    center(data.u);
  }
}

Dataset leading_samples(const Dataset& data,
                        const std::function<std::size_t(std::size_t, const Record&, std::size_t)>& take) {
  Dataset sub;
  for (std::size_t i = 0; i < data.records.size(); ++i) {
    const Record& r = data.records[i];
    const std::size_t n = take(i, r, sub.x.size());
    if (n == kEndSelection) break;
    Record nr = r;
    nr.size = std::min(n, r.size);
    nr.offset = sub.x.size();
    sub.x.insert(sub.x.end(), data.x_of(r), data.x_of(r) + nr.size);
    if (data.has_u()) sub.u.insert(sub.u.end(), data.u_of(r), data.u_of(r) + nr.size);
    sub.records.push_back(nr);
  }
  return sub;
}

double pooled_record_variance(const Dataset& data) {
  double ss = 0.0;
  std::size_t n = 0;
  for (const Record& r : data.records) {
    const double* x = data.x_of(r);
    double mean = 0.0;
    for (std::size_t i = 0; i < r.size; ++i) mean += x[i];
    mean /= double(std::max<std::size_t>(r.size, 1));
    for (std::size_t i = 0; i < r.size; ++i) ss += (x[i] - mean) * (x[i] - mean);
    n += r.size;
  }
  return n > 1 ? ss / double(n - 1) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace vehs
