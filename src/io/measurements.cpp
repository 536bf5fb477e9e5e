#include "vehs/io/measurements.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>

#include "vehs/io/atomic_file.hpp"
#include "vehs/io/path_text.hpp"
#include "readers.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"

namespace vehs {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Records whose mean intervals agree within 1e-3 share one clock: each gets the pooled interval
/// (the mean over all steps), so that jittered time stamps do not make records disagree.
void pool_intervals(Dataset& d) {
  double steps = 0.0, span = 0.0;
  for (const auto& r : d.records)
    if (r.size > 1) steps += static_cast<double>(r.size - 1), span += r.dt * static_cast<double>(r.size - 1);
  if (!(steps > 0.0)) return;
  const double pooled = span / steps;
  for (const auto& r : d.records)
    if (std::abs(r.dt - pooled) > 1e-3 * pooled) return;
  for (auto& r : d.records) r.dt = pooled;
}

void add_warnings(const std::string& path, const ReadOptions& o, ReadSummary& s) {
  if (s.max_jitter > o.jitter_warning)
    s.warnings.push_back(path + ": time steps deviate from the sampling interval by up to " +
                         detail::format_number(100.0 * s.max_jitter, 3) + " % (accepted up to " +
                         detail::format_number(100.0 * o.jitter_tolerance, 3) + " %: jitter_tolerance)");
  if (s.gaps + s.missing_runs > 0)
    s.warnings.push_back(path + ": records split at " + std::to_string(s.gaps) + " time gap(s) and " +
                         std::to_string(s.missing_runs) + " run(s) of missing values (" +
                         std::to_string(s.missing_rows) + " rows); " + std::to_string(s.dropped_pieces) +
                         " piece(s) shorter than " + std::to_string(o.min_samples) + " samples dropped (" +
                         std::to_string(s.dropped_samples) + " samples)");
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
  if (!(jitter_tolerance > 0.0 && jitter_tolerance < 0.5)) return "jitter_tolerance must be in (0, 0.5)";
  if (!(jitter_warning >= 0.0)) return "jitter_warning must be >= 0";
  return "";
}

std::string WriteColumns::invalid_reason() const {
  if (precision < 1 || precision > 17) return "precision must be in [1, 17] significant digits";
  return "";
}

void ReadSummary::merge(const ReadSummary& o) {
  gaps += o.gaps;
  missing_runs += o.missing_runs;
  missing_rows += o.missing_rows;
  dropped_pieces += o.dropped_pieces;
  dropped_samples += o.dropped_samples;
  max_jitter = std::max(max_jitter, o.max_jitter);
  warnings.insert(warnings.end(), o.warnings.begin(), o.warnings.end());
}

namespace {

/// The reader of a file named `name` (by extension: .npy binary, else CSV) over its bytes.
Dataset read_format(std::istream& in, const std::string& name, const ReadOptions& options, ReadSummary& s) {
  if (ends_with(name, ".mat")) throw Error(name + ": .mat files are read from a path (libmatio), not a stream");
  return ends_with(name, ".npy") ? io_detail::read_npy(in, name, options, s) : io_detail::read_csv(in, name, options, s);
}

/// A binary format named by its extension that the readers do not take (nullptr: none).
const char* unread_format(const std::string& path) {
  for (const char* ext : {".npz", ".xlsx", ".xls", ".h5", ".hdf5", ".parquet", ".zip", ".gz", ".tdms"})
    if (ends_with(path, ext)) return ext;
  return nullptr;
}

/// Refuses a path that is not a regular file before anything opens it: opening a FIFO waits for
/// a writer for ever, a device never ends.
void require_regular_file(const std::string& path) {
  check_path_text(path, "measurement file");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(path + ": cannot open measurement file (" + std::strerror(errno) + ")");
  if (S_ISREG(st.st_mode)) return;
  const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                     : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                     : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                                                                   : "not a regular file";
  throw Error(path + ": is " + kind + "; measurement files must be regular files");
}

Dataset read_file(const std::string& path, const ReadOptions& options, ReadSummary& s) {
  if (ends_with(path, ".mat")) return io_detail::read_mat(path, options, s);
  if (const char* other = unread_format(path))
    throw Error(path + ": " + other + " files are not read (CSV text, NumPy .npy and MATLAB .mat are)");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(path + ": cannot open measurement file");
  return read_format(file, path, options, s);
}

Dataset read_one(const std::string& path, std::istream* in, const ReadOptions& options, ReadSummary& summary) {
  if (auto why = options.invalid_reason(); !why.empty()) throw Error(path + ": " + why);
  ReadSummary s;
  Dataset d;
  if (in) {
    d = read_format(*in, path, options, s);
  } else {
    require_regular_file(path);
    d = read_file(path, options, s);
  }
  add_warnings(path, options, s);
  summary.merge(s);
  return d;
}

}  // namespace

namespace io_detail {

std::optional<std::size_t> bytes_left(std::istream& in) {
  const std::streampos here = in.tellg();
  if (here == std::streampos(-1)) {
    in.clear();
    return std::nullopt;
  }
  in.seekg(0, std::ios::end);
  const std::streampos end = in.tellg();
  in.clear();
  in.seekg(here);
  if (end == std::streampos(-1) || !in) {
    in.clear();
    return std::nullopt;
  }
  return end > here ? static_cast<std::size_t>(end - here) : 0;
}

}  // namespace io_detail

Dataset read_measurements(const std::string& path, const ReadOptions& options, ReadSummary* summary) {
  ReadSummary local;
  Dataset d = read_one(path, nullptr, options, summary ? *summary : local);
  if (!(options.dt > 0.0)) pool_intervals(d);
  return d;
}

Dataset read_measurements(std::istream& in, const std::string& name, const ReadOptions& options,
                          ReadSummary* summary) {
  ReadSummary local;
  Dataset d = read_one(name, &in, options, summary ? *summary : local);
  if (!(options.dt > 0.0)) pool_intervals(d);
  return d;
}

Dataset read_measurements(const std::vector<std::string>& paths, const ReadOptions& options, ReadSummary* summary) {
  require(!paths.empty(), "no measurement files given");
  ReadSummary local;
  ReadSummary& s = summary ? *summary : local;
  Dataset all = read_one(paths.front(), nullptr, options, s);
  for (std::size_t i = 1; i < paths.size(); ++i) all.append(read_one(paths[i], nullptr, options, s));
  if (!(options.dt > 0.0)) pool_intervals(all);
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
