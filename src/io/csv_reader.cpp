// CSV as loggers write it (see vehs/io/measurements.hpp): streamed in chunks of 4 MiB (or the
// file, when smaller), one pass.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <istream>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>
#include <unordered_set>

#include <fast_float/fast_float.h>

#include "vehs/io/detail/iso_time.hpp"
#include "readers.hpp"
#include "vehs/core/error.hpp"

namespace vehs::io_detail {

namespace {

std::string_view trim(std::string_view f) {
  while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
  while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) f.remove_suffix(1);
  if (f.size() >= 2 && ((f.front() == '"' && f.back() == '"') || (f.front() == '\'' && f.back() == '\'')))
    f = f.substr(1, f.size() - 2);
  return f;
}

/// The delimiter of a header row: the most frequent of ',', ';' and tab (',' when none).
char detect_delimiter(std::string_view header) {
  const std::array<char, 3> candidates{',', ';', '\t'};
  char best = ',';
  std::ptrdiff_t most = 0;
  for (char c : candidates) {
    const auto n = std::count(header.begin(), header.end(), c);
    if (n > most) most = n, best = c;
  }
  return best;
}

/// The fields of a line; a delimiter inside double quotes ("a, b", "1,234.5") does not split.
void split(std::string_view line, char delimiter, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '"') quoted = !quoted;
    else if (line[i] == delimiter && !quoted) fields.push_back(line.substr(start, i - start)), start = i + 1;
  }
  fields.push_back(line.substr(start));
}

bool is_comment_or_blank(std::string_view line) {
  const auto p = line.find_first_not_of(" \t\r");
  return p == std::string_view::npos || line[p] == '#' || line[p] == '%';
}

/// A spreadsheet's or logger's missing value: NA, N/A, #N/A, null (any case).
bool is_missing_token(std::string_view f) {
  if (f.size() > 4) return false;
  std::string lower(f);
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return lower == "na" || lower == "n/a" || lower == "#n/a" || lower == "null";
}

/// Lines expected in a stream of `bytes` bytes whose first chunk is `first` (its line density,
/// extrapolated): the reserve for the columns, without a second pass over the file.
std::size_t estimate_lines(std::string_view first, std::size_t bytes) {
  if (first.empty()) return 0;
  const auto lines = static_cast<double>(std::count(first.begin(), first.end(), '\n') + 1);
  const double total = static_cast<double>(std::max(bytes, first.size()));
  return static_cast<std::size_t>(lines * total / static_cast<double>(first.size())) + 1;
}

class CsvParser {
 public:
  CsvParser(const std::string& path, const ReadOptions& o, ReadSummary& summary)
      : path_(path), o_(o), summary_(summary) {}

  void set_line_estimate(std::size_t lines) { line_estimate_ = lines; }

  void line(std::string_view text) {
    ++line_no_;
    if (line_no_ == 1 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 BOM
    if (is_comment_or_blank(text) || is_semicolon_comment(text)) return;
    if (!rb_) return header(text);
    split(text, delimiter_, fields_);
    if (!rows_seen_++ && units_row()) return;
    if (static_cast<int>(fields_.size()) <= need_)
      throw Error(path_ + ": line " + std::to_string(line_no_) + ": has " + std::to_string(fields_.size()) +
                  " fields, expected " + std::to_string(ncols_));
    for (std::size_t i = static_cast<std::size_t>(ncols_); i < fields_.size(); ++i)  // empty trailing fields are fine
      if (!trim(fields_[i]).empty())
        throw Error(path_ + ": line " + std::to_string(line_no_) + ": has " + std::to_string(fields_.size()) +
                    " fields, the header " + std::to_string(ncols_) + " (a shifted or merged row?)");
    Row r;
    r.line = line_no_;
    if (idx_.traj >= 0) {  // (RecordBuilder checks it)
      r.id = value(idx_.traj, o_.traj_column);
      r.id_text = trim(fields_[static_cast<std::size_t>(idx_.traj)]);
    }
    if (idx_.t >= 0) r.t = time_value();
    r.x = value(idx_.x, o_.x_column);
    if (idx_.u >= 0) r.u = value(idx_.u, o_.u_column);
    if (idx_.y >= 0) r.y = value(idx_.y, o_.y_column);
    rb_->row(r);
  }

  Dataset finish() {
    if (!rb_) throw Error(path_ + ": empty file (no header row)");
    rb_->finish();
    if (d_.x.capacity() - d_.x.size() > d_.x.size() / 8) d_.x.shrink_to_fit();
    return std::move(d_);
  }

 private:
  /// A line starting with ';' (INI-style loggers' comments): before the header, and after it
  /// unless ';' delimits the fields (there it is an empty first field).
  bool is_semicolon_comment(std::string_view text) const {
    const auto p = text.find_first_not_of(" \t");
    return p != std::string_view::npos && text[p] == ';' && (!rb_ || delimiter_ != ';');
  }

  void header(std::string_view text) {
    if (text.substr(0, 2) == "\xFF\xFE" || text.substr(0, 2) == "\xFE\xFF" || text.find('\0') != text.npos)
      throw Error(path_ + ": line " + std::to_string(line_no_) +
                  ": UTF-16 text or binary data (save the file as UTF-8 text; .npy and .mat files are read by name)");
    if (const std::size_t cr = text.find('\r'); cr != text.npos && cr + 1 < text.size())
      throw Error(path_ + ": line ends are '\\r' alone (classic Mac OS): convert them to '\\n'");
    delimiter_ = detect_delimiter(text);
    split(text, delimiter_, fields_);
    std::vector<std::string> names;
    for (auto f : fields_) names.emplace_back(trim(f));
    while (!names.empty() && names.back().empty()) names.pop_back();  // trailing delimiter
    ncols_ = static_cast<int>(names.size());
    idx_ = index_columns(names, o_, path_, "column");
    need_ = std::max({idx_.x, idx_.t, idx_.traj, idx_.u, idx_.y});
    d_.x.reserve(line_estimate_);
    if (idx_.u >= 0) d_.u.reserve(line_estimate_);
    if (idx_.y >= 0) d_.y.reserve(line_estimate_);
    rb_ = std::make_unique<RecordBuilder>(d_, path_, o_, idx_.present(), summary_);
  }

  /// A row of units under the header ("s,mm,V", "[s];[mm]", ",s,mm" or "-,s,mm" for a unitless
  /// column): the first row after the header when none of its fields is a number or a missing
  /// value and one at least is text (skipped, said in the summary).
  bool units_row() {
    bool text = false;
    for (auto f : fields_) {
      f = trim(f);
      if (f.empty() || f == "-") continue;
      if (is_missing_token(f)) return false;
      text = true;
      double v = 0.0;
      const auto r = fast_float::from_chars(f.data(), f.data() + f.size(), v);
      if (r.ptr != f.data() || std::isdigit(static_cast<unsigned char>(f.front())) || f.front() == '-' || f.front() == '+' ||
          f.front() == '.')
        return false;
    }
    if (!text) return false;
    summary_.warnings.push_back(path_ + ": line " + std::to_string(line_no_) + " read as a row of units and skipped");
    return true;
  }

  /// The time column: a number, or an ISO-8601 stamp in seconds since the file's first stamp.
  double time_value() {
    const std::string_view f = trim(fields_[static_cast<std::size_t>(idx_.t)]);
    if (f.size() < 19 || f[4] != '-') return value(idx_.t, o_.t_column);
    const std::optional<IsoTime> t = parse_iso8601(f);
    if (!t) throw Error(rb_->where(line_no_) + ": column '" + o_.t_column + "': '" + std::string(f) +
                        "' is not a number nor an ISO-8601 time (YYYY-MM-DDThh:mm:ss[.fff][Z|+hh:mm])");
    if (!iso_base_) iso_base_ = t->seconds;
    return static_cast<double>(t->seconds - *iso_base_) + t->fraction;
  }

  /// The number in a field; NaN for a missing value (empty, "nan", or a spreadsheet's NA, N/A,
  /// #N/A, null: RecordBuilder decides). With a ';' or tab delimiter a decimal comma ("0,125")
  /// is read as a decimal point (European locales).
  double value(int column, const std::string& name) {
    std::string_view f = trim(fields_[static_cast<std::size_t>(column)]);
    if (f.empty()) return std::numeric_limits<double>::quiet_NaN();
    if (f.front() == '+') f.remove_prefix(1);
    double v = 0.0;
    auto r = fast_float::from_chars(f.data(), f.data() + f.size(), v);
    if (r.ec == std::errc() && r.ptr == f.data() + f.size()) return v;
    // the rare fields that are not plain numbers
    if (is_missing_token(f)) return std::numeric_limits<double>::quiet_NaN();
    if (delimiter_ != ',' && std::count(f.begin(), f.end(), ',') == 1 && f.find('.') == f.npos) {
      std::string dotted(f);
      dotted[dotted.find(',')] = '.';
      r = fast_float::from_chars(dotted.data(), dotted.data() + dotted.size(), v);
      if (r.ec == std::errc() && r.ptr == dotted.data() + dotted.size()) return v;
    }
    throw Error(rb_->where(line_no_) + ": column '" + name + "': '" + std::string(f) + "' is not a number");
  }

  const std::string& path_;
  const ReadOptions& o_;
  ReadSummary& summary_;
  std::size_t line_estimate_ = 0;
  std::size_t line_no_ = 0;
  char delimiter_ = ',';
  int ncols_ = 0, need_ = 0;
  ColumnIndex idx_;
  Dataset d_;
  std::unique_ptr<RecordBuilder> rb_;
  std::vector<std::string_view> fields_;
  std::size_t rows_seen_ = 0;
  std::optional<long long> iso_base_;  ///< whole seconds of the first ISO-8601 stamp
};

}  // namespace

Dataset read_csv(std::istream& in, const std::string& path, const ReadOptions& o, ReadSummary& summary,
                 std::size_t chunk_bytes) {
  const std::optional<std::size_t> size = bytes_left(in);
  CsvParser parser(path, o, summary);
  // one chunk for a small file (no 4 MiB buffer to zero for a few lines)
  std::vector<char> buf(std::max<std::size_t>(1, size ? std::min(chunk_bytes, *size + 1) : chunk_bytes));
  std::string carry;  // an incomplete line from the previous chunk
  bool first = true;
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n == 0) break;
    std::string_view chunk(buf.data(), n);
    if (first) parser.set_line_estimate(estimate_lines(chunk, size.value_or(n))), first = false;
    std::size_t pos = 0;
    if (!carry.empty()) {
      const auto nl = chunk.find('\n');
      if (nl == std::string_view::npos) {
        carry.append(chunk);
        continue;
      }
      carry.append(chunk.substr(0, nl));
      parser.line(carry);
      carry.clear();
      pos = nl + 1;
    }
    while (true) {
      const auto nl = chunk.find('\n', pos);
      if (nl == std::string_view::npos) {
        carry.assign(chunk.substr(pos));
        break;
      }
      parser.line(chunk.substr(pos, nl - pos));
      pos = nl + 1;
    }
  }
  if (in.bad()) throw Error(path + ": read error");
  if (!carry.empty()) parser.line(carry);
  return parser.finish();
}

ColumnIndex index_columns(const std::vector<std::string>& names, const ReadOptions& o, const std::string& path,
                          const char* kind) {
  ColumnIndex c;
  std::string all;
  std::unordered_set<std::string_view> seen;  // (a header of 10^4 names is checked in linear time)
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& n = names[i];
    if (!n.empty() && !seen.insert(n).second)
      throw Error(path + ": the " + std::string(kind) + " name '" + n + "' appears twice");
    const int k = static_cast<int>(i);
    if (n == o.x_column) c.x = k;
    if (n == o.t_column) c.t = k;
    if (n == o.traj_column) c.traj = k;
    if (o.read_u && n == o.u_column) c.u = k;
    if (o.read_y && n == o.y_column) c.y = k;
    if (all.size() < 200) all += (all.empty() ? "" : ", ") + n;  // the message stays one readable line
  }
  if (all.size() >= 200) all = all.substr(0, 200) + " ...";
  if (c.x < 0) throw Error(path + ": no " + kind + " '" + o.x_column + "' (" + kind + "s: " + all + ")");
  if (c.t < 0 && !(o.dt > 0.0))
    throw Error(path + ": no time " + kind + " '" + o.t_column + "' (" + kind + "s: " + all +
                "); give the sampling interval 'dt' in the config");
  if (o.require_u && c.u < 0)
    throw Error(path + ": no drive " + kind + " '" + o.u_column + "' (" + kind + "s: " + all +
                ") but the model uses the term 'u'");
  return c;
}

}  // namespace vehs::io_detail
