#include "vehs/io/measurements.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <set>
#include <sstream>

#include <fast_float/fast_float.h>

#include "vehs/conventions.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/core/error.hpp"

namespace vehs {

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File open_or_throw(const std::string& path) {
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) throw Error(path + ": cannot open measurement file");
  return f;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string trim_field(std::string_view f) {
  while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
  while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) f.remove_suffix(1);
  if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
  return std::string(f);
}

// Builds records incrementally, checking uniform sampling and contiguity.
class RecordBuilder {
 public:
  RecordBuilder(Dataset& d, std::string source, const ReadOptions& o, bool has_time,
                bool has_traj)
      : d_(d), source_(std::move(source)), o_(o), has_time_(has_time), has_traj_(has_traj) {}

  std::string where(std::size_t line) const {
    std::string s = source_ + ": line " + std::to_string(line);
    if (has_traj_) s += " (record traj=" + std::to_string(cur_.id) + ")";
    return s;
  }

  void sample(std::size_t line, long long id, double t, double x) {
    if (!open_ || (has_traj_ && id != cur_.id)) {
      close();
      if (has_traj_ && !seen_.insert(id).second)
        throw Error(source_ + ": line " + std::to_string(line) + ": record traj=" +
                    std::to_string(id) + " appears again after other records (rows of one "
                    "record must be contiguous)");
      cur_ = Record{};
      cur_.source = source_;
      cur_.id = id;
      cur_.first_line = line;
      cur_.offset = d_.x.size() - 1;  // x already pushed by caller
      cur_.t0 = has_time_ ? t : 0.0;
      last_t_ = t;
      ref_dt_ = 0.0;
      open_ = true;
      return;
    }
    if (has_time_) {
      const double step = t - last_t_;
      if (!(step > 0.0))
        throw Error(where(line) + ": time " + num(t) + " does not increase (previous " +
                    num(last_t_) + ")");
      if (ref_dt_ == 0.0) {
        ref_dt_ = step;
      } else if (std::abs(step - ref_dt_) > conventions::sampling_jitter_tolerance * ref_dt_) {
        throw Error(where(line) + ": non-uniform sampling: interval " + num(step) +
                    " differs from " + num(ref_dt_) + " (relative jitter " +
                    num(std::abs(step - ref_dt_) / ref_dt_) + " > 1e-6)");
      }
      last_t_ = t;
    }
    (void)x;
  }

  void close() {
    if (!open_) return;
    open_ = false;
    cur_.size = d_.x.size() - cur_.offset - (pending_ ? 1 : 0);
    if (cur_.size < o_.min_samples)
      throw Error(source_ + ": line " + std::to_string(cur_.first_line) + ": record " +
                  (has_traj_ ? "traj=" + std::to_string(cur_.id) + " " : "") + "has only " +
                  std::to_string(cur_.size) + " samples (at least " +
                  std::to_string(o_.min_samples) + " needed)");
    if (has_time_) {
      cur_.dt = cur_.size > 1 ? (last_t_ - cur_.t0) / static_cast<double>(cur_.size - 1) : 0.0;
    } else {
      cur_.dt = o_.dt;
      cur_.t0 = 0.0;
    }
    d_.records.push_back(cur_);
  }

  // Called before pushing the sample of a new row so that close() knows one sample is pending.
  void set_pending(bool p) { pending_ = p; }

  static std::string num(double v) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
  }

 private:
  Dataset& d_;
  std::string source_;
  const ReadOptions& o_;
  bool has_time_, has_traj_;
  bool open_ = false;
  bool pending_ = false;
  Record cur_;
  double last_t_ = 0.0, ref_dt_ = 0.0;
  std::set<long long> seen_;
};

std::size_t count_lines(std::FILE* f) {
  std::vector<char> buf(1 << 22);
  std::size_t lines = 0, n;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0)
    lines += static_cast<std::size_t>(std::count(buf.data(), buf.data() + n, '\n'));
  std::rewind(f);
  return lines + 1;
}

Dataset read_csv(const std::string& path, const ReadOptions& o) {
  File file = open_or_throw(path);
  const std::size_t line_estimate = count_lines(file.get());
  std::vector<char> buf(1 << 22);
  std::string carry;  // an incomplete line from the previous chunk
  std::size_t line_no = 0;

  // column roles
  int ix = -1, it = -1, itraj = -1, iu = -1, iy = -1;
  int ncols = 0;
  bool header_done = false;
  Dataset d;
  std::unique_ptr<RecordBuilder> rb;
  std::vector<std::string_view> fields;

  auto parse_header = [&](std::string_view line) {
    std::vector<std::string> names;
    std::size_t start = 0;
    while (true) {
      const auto c = line.find(',', start);
      names.push_back(trim_field(line.substr(start, c == std::string_view::npos ? line.npos : c - start)));
      if (c == std::string_view::npos) break;
      start = c + 1;
    }
    while (!names.empty() && names.back().empty()) names.pop_back();  // trailing comma
    ncols = static_cast<int>(names.size());
    for (int i = 0; i < ncols; ++i) {
      const auto& n = names[static_cast<std::size_t>(i)];
      if (n == o.x_column) ix = i;
      if (n == o.t_column) it = i;
      if (n == o.traj_column) itraj = i;
      if (o.read_u && n == o.u_column) iu = i;
      if (o.read_y && n == o.y_column) iy = i;
    }
    std::string all;
    for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
    if (ix < 0)
      throw Error(path + ": no column '" + o.x_column + "' in the header (columns: " + all + ")");
    if (it < 0 && !(o.dt > 0.0))
      throw Error(path + ": no time column '" + o.t_column + "' (columns: " + all +
                  "); give the sampling interval 'dt' in the config");
    if (o.require_u && iu < 0)
      throw Error(path + ": no drive column '" + o.u_column + "' (columns: " + all +
                  ") but the model uses the term 'u'");
    d.x.reserve(line_estimate);
    if (iu >= 0) d.u.reserve(line_estimate);
    if (iy >= 0) d.y.reserve(line_estimate);
    rb = std::make_unique<RecordBuilder>(d, path, o, it >= 0, itraj >= 0);
    header_done = true;
  };

  auto parse_double = [&](std::string_view f, const char* what) {
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) f.remove_suffix(1);
    if (!f.empty() && f.front() == '+') f.remove_prefix(1);
    double v = 0.0;
    auto r = fast_float::from_chars(f.data(), f.data() + f.size(), v);
    if (f.empty() || r.ec != std::errc() || r.ptr != f.data() + f.size())
      throw Error(rb->where(line_no) + ": column '" + what + "': '" + std::string(f) +
                  "' is not a number");
    if (!std::isfinite(v))
      throw Error(rb->where(line_no) + ": column '" + what + "' is " + std::string(f) +
                  " (NaN or infinite values are not allowed)");
    return v;
  };

  auto parse_row = [&](std::string_view line) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (!header_done) {
      parse_header(line);
      return;
    }
    if (line.find_first_not_of(" \t") == std::string_view::npos) return;  // blank line
    fields.clear();
    std::size_t start = 0;
    while (true) {
      const auto c = line.find(',', start);
      fields.push_back(line.substr(start, c == std::string_view::npos ? line.npos : c - start));
      if (c == std::string_view::npos) break;
      start = c + 1;
    }
    const int need = std::max({ix, it, itraj, iu, iy});
    if (static_cast<int>(fields.size()) <= need)
      throw Error(path + ": line " + std::to_string(line_no) + ": has " +
                  std::to_string(fields.size()) + " fields, expected " + std::to_string(ncols));
    long long id = 0;
    if (itraj >= 0) {
      const double v = parse_double(fields[static_cast<std::size_t>(itraj)], o.traj_column.c_str());
      if (v != std::floor(v) || !(std::abs(v) < 9e15))  // (a larger id would overflow the conversion)
        throw Error(path + ": line " + std::to_string(line_no) + ": record id '" +
                    std::string(fields[static_cast<std::size_t>(itraj)]) + "' is not an integer below 9e15");
      id = static_cast<long long>(v);
    }
    const double t = it >= 0 ? parse_double(fields[static_cast<std::size_t>(it)], o.t_column.c_str()) : 0.0;
    const double x = parse_double(fields[static_cast<std::size_t>(ix)], o.x_column.c_str());
    const double u = iu >= 0 ? parse_double(fields[static_cast<std::size_t>(iu)], o.u_column.c_str()) : 0.0;
    const double y = iy >= 0 ? parse_double(fields[static_cast<std::size_t>(iy)], o.y_column.c_str()) : 0.0;
    d.x.push_back(x);
    if (iu >= 0) d.u.push_back(u);
    if (iy >= 0) d.y.push_back(y);
    rb->set_pending(true);
    rb->sample(line_no, id, t, x);
    rb->set_pending(false);
  };

  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), file.get())) > 0) {
    std::string_view chunk(buf.data(), n);
    std::size_t pos = 0;
    if (!carry.empty()) {
      const auto nl = chunk.find('\n');
      if (nl == std::string_view::npos) {
        carry.append(chunk);
        continue;
      }
      carry.append(chunk.substr(0, nl));
      parse_row(carry);
      carry.clear();
      pos = nl + 1;
    }
    while (true) {
      const auto nl = chunk.find('\n', pos);
      if (nl == std::string_view::npos) {
        carry.assign(chunk.substr(pos));
        break;
      }
      parse_row(chunk.substr(pos, nl - pos));
      pos = nl + 1;
    }
  }
  if (std::ferror(file.get())) throw Error(path + ": read error");
  if (!carry.empty()) parse_row(carry);
  if (!header_done) throw Error(path + ": empty file (no header row)");
  rb->close();
  if (d.records.empty()) throw Error(path + ": no data rows after the header");
  // shrink only when much was over-reserved: shrink_to_fit copies, which would double the
  // peak memory of a large file for the two spare elements a header leaves
  if (d.x.capacity() - d.x.size() > d.x.size() / 8) d.x.shrink_to_fit();
  return d;
}

// ---------------------------------------------------------------- .npy (structured dtype)

struct NpyField {
  std::string name;
  char kind = 'f';  // 'f' float, 'i' signed int
  int size = 8;
  std::size_t offset = 0;
};

std::vector<NpyField> parse_descr(const std::string& header, const std::string& path,
                                  std::size_t& shape0) {
  auto fail = [&](const std::string& m) -> std::vector<NpyField> {
    throw Error(path + ": unsupported .npy header (" + m + "); expected a 1-D structured array "
                "with fields like [('traj','<i8'),('t','<f8'),('x','<f8')]");
  };
  if (header.find("'fortran_order': True") != std::string::npos) fail("Fortran order");
  const auto sh = header.find("'shape':");
  if (sh == std::string::npos) return fail("no shape");
  const auto lp = header.find('(', sh), rp = header.find(')', sh);
  const std::string shape = header.substr(lp + 1, rp - lp - 1);
  char* end = nullptr;
  shape0 = std::strtoull(shape.c_str(), &end, 10);
  std::string rest(end);
  rest.erase(std::remove_if(rest.begin(), rest.end(), ::isspace), rest.end());
  if (!(rest.empty() || rest == ",")) fail("shape must be 1-D");
  const auto ds = header.find("'descr':");
  if (ds == std::string::npos) return fail("no descr");
  std::vector<NpyField> fields;
  std::size_t pos = header.find_first_not_of(' ', ds + 8);
  auto type_of = [&](const std::string& t, NpyField& f) {
    if (t.size() < 3 || (t[0] != '<' && t[0] != '|' && t[0] != '=')) fail("only little-endian");
    f.kind = t[1];
    f.size = std::atoi(t.c_str() + 2);
    if (!((f.kind == 'f' && (f.size == 4 || f.size == 8)) ||
          (f.kind == 'i' && (f.size == 4 || f.size == 8))))
      fail("field type " + t);
  };
  if (header[pos] == '\'') {  // plain dtype: a single column named x
    const auto q = header.find('\'', pos + 1);
    NpyField f;
    f.name = "x";
    type_of(header.substr(pos + 1, q - pos - 1), f);
    fields.push_back(f);
    return fields;
  }
  if (header[pos] != '[') return fail("descr");
  std::size_t offset = 0;
  while (true) {
    const auto open = header.find('(', pos);
    const auto close_list = header.find(']', pos);
    if (open == std::string::npos || open > close_list) break;
    const auto q1 = header.find('\'', open), q2 = header.find('\'', q1 + 1);
    const auto q3 = header.find('\'', q2 + 1), q4 = header.find('\'', q3 + 1);
    const auto close = header.find(')', open);
    if (q4 == std::string::npos || q4 > close) return fail("field entry");
    NpyField f;
    f.name = header.substr(q1 + 1, q2 - q1 - 1);
    type_of(header.substr(q3 + 1, q4 - q3 - 1), f);
    f.offset = offset;
    offset += static_cast<std::size_t>(f.size);
    fields.push_back(f);
    pos = close + 1;
  }
  if (fields.empty()) return fail("no fields");
  return fields;
}

double field_value(const char* row, const NpyField& f) {
  if (f.kind == 'f') {
    if (f.size == 8) {
      double v;
      std::memcpy(&v, row + f.offset, 8);
      return v;
    }
    float v;
    std::memcpy(&v, row + f.offset, 4);
    return v;
  }
  if (f.size == 8) {
    long long v;
    std::memcpy(&v, row + f.offset, 8);
    return static_cast<double>(v);
  }
  int v;
  std::memcpy(&v, row + f.offset, 4);
  return v;
}

Dataset read_npy(const std::string& path, const ReadOptions& o) {
  File file = open_or_throw(path);
  char magic[8];
  if (std::fread(magic, 1, 8, file.get()) != 8 || std::memcmp(magic, "\x93NUMPY", 6) != 0)
    throw Error(path + ": not a NumPy .npy file");
  std::size_t hlen = 0;
  if (magic[6] == 1) {
    unsigned char b[2];
    if (std::fread(b, 1, 2, file.get()) != 2) throw Error(path + ": truncated .npy header");
    hlen = b[0] | (b[1] << 8);
  } else {
    unsigned char b[4];
    if (std::fread(b, 1, 4, file.get()) != 4) throw Error(path + ": truncated .npy header");
    hlen = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::size_t>(b[3]) << 24);
  }
  if (hlen > (std::size_t{1} << 20))  // numpy writes headers of < 10 kB; a length from a corrupt file
    throw Error(path + ": .npy header of " + std::to_string(hlen) + " bytes (corrupt file?)");  // is no allocation size
  std::string header(hlen, '\0');
  if (std::fread(header.data(), 1, hlen, file.get()) != hlen)
    throw Error(path + ": truncated .npy header");
  std::size_t rows = 0;
  const auto fields = parse_descr(header, path, rows);
  std::size_t row_size = 0;
  for (const auto& f : fields) row_size = std::max(row_size, f.offset + static_cast<std::size_t>(f.size));
  const NpyField *fx = nullptr, *ft = nullptr, *ftraj = nullptr, *fu = nullptr, *fy = nullptr;
  for (const auto& f : fields) {
    if (f.name == o.x_column) fx = &f;
    if (f.name == o.t_column) ft = &f;
    if (f.name == o.traj_column) ftraj = &f;
    if (o.read_u && f.name == o.u_column) fu = &f;
    if (o.read_y && f.name == o.y_column) fy = &f;
  }
  if (!fx) throw Error(path + ": no field '" + o.x_column + "' in the .npy dtype");
  if (!ft && !(o.dt > 0.0))
    throw Error(path + ": no time field '" + o.t_column + "'; give 'dt' in the config");
  if (o.require_u && !fu)
    throw Error(path + ": no drive field '" + o.u_column + "' but the model uses the term 'u'");
  Dataset d;
  d.x.reserve(rows);
  if (fu) d.u.reserve(rows);
  if (fy) d.y.reserve(rows);
  RecordBuilder rb(d, path, o, ft != nullptr, ftraj != nullptr);
  const std::size_t chunk_rows = std::max<std::size_t>(1, (1u << 22) / row_size);
  std::vector<char> buf(chunk_rows * row_size);
  std::size_t row = 0;
  while (row < rows) {
    const std::size_t want = std::min(chunk_rows, rows - row);
    if (std::fread(buf.data(), row_size, want, file.get()) != want)
      throw Error(path + ": truncated .npy data (expected " + std::to_string(rows) + " rows)");
    for (std::size_t k = 0; k < want; ++k, ++row) {
      const char* r = buf.data() + k * row_size;
      const double x = field_value(r, *fx);
      const double t = ft ? field_value(r, *ft) : 0.0;
      if (!std::isfinite(x) || !std::isfinite(t))
        throw Error(path + ": row " + std::to_string(row) + ": NaN or infinite value");
      d.x.push_back(x);
      if (fu) d.u.push_back(field_value(r, *fu));
      if (fy) d.y.push_back(field_value(r, *fy));
      rb.set_pending(true);
      // .npy rows are reported 0-based as "row"; RecordBuilder says "line" = row + 1
      const double id = ftraj ? field_value(r, *ftraj) : 0.0;
      if (id != std::floor(id) || !(std::abs(id) < 9e15))  // (a larger id would overflow the conversion)
        throw Error(path + ": row " + std::to_string(row) + ": record id " + std::to_string(id) +
                    " is not an integer below 9e15");
      rb.sample(row + 1, static_cast<long long>(id), t, x);
      rb.set_pending(false);
    }
  }
  rb.close();
  if (d.records.empty()) throw Error(path + ": no rows");
  return d;
}

void write_csv(std::ostream& os, const Dataset& d, const WriteColumns& c) {
  const bool wy = c.with_y && d.has_y(), wu = c.with_u && d.has_u();
  os << "traj,t,x" << (wy ? ",y" : "") << (wu ? ",u" : "") << "\n";
  std::vector<char> buf;
  buf.reserve(1 << 20);
  char tmp[64];
  auto put = [&](double v) {
    auto r = std::to_chars(tmp, tmp + sizeof tmp, v, std::chars_format::general, c.precision);
    buf.insert(buf.end(), tmp, r.ptr);
  };
  for (const auto& rec : d.records) {
    char idbuf[24];
    auto idr = std::to_chars(idbuf, idbuf + sizeof idbuf, rec.id);
    for (std::size_t i = 0; i < rec.size; ++i) {
      const std::size_t k = rec.offset + i;
      buf.insert(buf.end(), idbuf, idr.ptr);
      buf.push_back(',');
      put(rec.t0 + static_cast<double>(i) * rec.dt);
      buf.push_back(',');
      put(d.x[k]);
      if (wy) buf.push_back(','), put(d.y[k]);
      if (wu) buf.push_back(','), put(d.u[k]);
      buf.push_back('\n');
      if (buf.size() > (1u << 20) - 256) {
        os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
      }
    }
  }
  os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

void write_npy(std::ostream& os, const Dataset& d, const WriteColumns& c) {
  const bool wy = c.with_y && d.has_y(), wu = c.with_u && d.has_u();
  std::string header = "{'descr': [('traj', '<i8'), ('t', '<f8'), ('x', '<f8')";
  if (wy) header += ", ('y', '<f8')";
  if (wu) header += ", ('u', '<f8')";
  header += "], 'fortran_order': False, 'shape': (" + std::to_string(d.total_samples()) + ",), }";
  // pad so that magic(6)+version(2)+len(4)+header is a multiple of 64, ending in '\n'
  const std::size_t pre = 12;
  std::size_t total = pre + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  const auto hl = static_cast<std::uint32_t>(header.size());
  const char version[2] = {2, 0};
  os.write("\x93NUMPY", 6);
  os.write(version, 2);
  const unsigned char len[4] = {static_cast<unsigned char>(hl & 0xff), static_cast<unsigned char>((hl >> 8) & 0xff),
                                static_cast<unsigned char>((hl >> 16) & 0xff), static_cast<unsigned char>(hl >> 24)};
  os.write(reinterpret_cast<const char*>(len), 4);
  os.write(header.data(), static_cast<std::streamsize>(header.size()));
  const std::size_t ncol = 3 + wy + wu;
  std::vector<char> buf;
  buf.reserve(ncol * 8 * 65536);
  for (const auto& rec : d.records) {
    for (std::size_t i = 0; i < rec.size; ++i) {
      const std::size_t k = rec.offset + i;
      const long long id = rec.id;
      const double t = rec.t0 + static_cast<double>(i) * rec.dt;
      char row[40];
      std::memcpy(row, &id, 8);
      std::memcpy(row + 8, &t, 8);
      std::memcpy(row + 16, &d.x[k], 8);
      std::size_t off = 24;
      if (wy) std::memcpy(row + off, &d.y[k], 8), off += 8;
      if (wu) std::memcpy(row + off, &d.u[k], 8), off += 8;
      buf.insert(buf.end(), row, row + off);
      if (buf.size() >= ncol * 8 * 65536) {
        os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
      }
    }
  }
  os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
}

}  // namespace

std::string ReadOptions::invalid_reason() const {
  if (x_column.empty()) return "the x column needs a name";
  if (!(dt >= 0.0) || !std::isfinite(dt)) return "dt must be >= 0 (0: from the time column)";
  if (min_samples < 2) return "records need at least 2 samples (min_samples >= 2)";
  if (require_u && !read_u) return "require_u needs read_u";
  return "";
}

std::string WriteColumns::invalid_reason() const {
  if (precision < 1 || precision > 17) return "precision must be in [1, 17] significant digits";
  return "";
}

Dataset read_measurements(const std::string& path, const ReadOptions& options) {
  if (auto why = options.invalid_reason(); !why.empty()) throw Error(path + ": " + why);
  return ends_with(path, ".npy") ? read_npy(path, options) : read_csv(path, options);
}

Dataset read_measurements(const std::vector<std::string>& paths, const ReadOptions& options) {
  require(!paths.empty(), "no measurement files given");
  Dataset all = read_measurements(paths.front(), options);
  for (std::size_t i = 1; i < paths.size(); ++i) all.append(read_measurements(paths[i], options));
  return all;
}

void write_measurements(const std::string& path, const Dataset& data, const WriteColumns& cols) {
  if (auto why = cols.invalid_reason(); !why.empty()) throw Error(path + ": " + why);
  write_file_atomically(path, [&](std::ostream& os) {
    if (ends_with(path, ".npy"))
      write_npy(os, data, cols);
    else
      write_csv(os, data, cols);
  });
}

}  // namespace vehs
