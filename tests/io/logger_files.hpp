#pragma once
// Files written the way data loggers and lab software write them, for the reader tests: time
// stamps with 6 decimals or as float32, ±0.2 ms jitter, comment headers, `;` or tab delimiters,
// a UTF-8 BOM, mm or m, a gap, a NaN run; 2-D .npy arrays (written here byte by byte) and
// MATLAB v4 .mat files (the simple format, written byte by byte: the reader goes through
// libmatio). None of this uses the library's writers.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace vehs::test {

struct LoggerStyle {
  std::string delimiter = ";";
  bool bom = true;
  std::vector<std::string> comments = {"# DataLogger 3000, firmware 2.1", "# channel 1: laser displacement",
                                       "# sample rate: 300 Hz"};
  std::string t_name = "time [s]", x_name = "disp [mm]", u_name = "acc [m/s^2]";
  int time_decimals = 6;       ///< fixed decimals of the time column (0: 17 significant digits)
  bool float32_time = false;   ///< time stamps rounded to float32 first
  double jitter = 0.0;         ///< time stamps move by a uniform ±jitter (deterministic)
  double t0 = 0.0;
  double length_factor = 1.0;  ///< x written as x·length_factor (1000: mm from m)
  std::size_t gap_at = 0, gap_rows = 0;  ///< rows [gap_at, gap_at + gap_rows) left out
  std::size_t nan_at = 0, nan_rows = 0;  ///< rows whose x is written "NaN" (first) or empty
  /// ISO-8601 stamps from 2026-11-25T23:59:50+01:00 (time_decimals decimals; crosses midnight
  /// after 10 s) instead of numbers
  bool iso_time = false;
  std::string units_row;       ///< written under the header when not empty ("s;mm;m/s^2")
};

/// A deterministic uniform number in [−1, 1) (the time-stamp jitter).
inline double jitter_unit(std::uint64_t& state) {
  state = state * 6364136223846793005ULL + 1442695040888963407ULL;
  return static_cast<double>(state >> 11) * 0x1.0p-52 - 1.0;
}

inline void write_logger_csv(const std::string& path, const std::vector<double>& x, const std::vector<double>& u,
                             double dt, const LoggerStyle& s) {
  std::ofstream f(path, std::ios::binary);
  if (s.bom) f << "\xEF\xBB\xBF";
  for (const auto& c : s.comments) f << c << "\r\n";
  f << '"' << s.t_name << '"' << s.delimiter << '"' << s.x_name << '"';
  if (!u.empty()) f << s.delimiter << '"' << s.u_name << '"';
  f << "\r\n";
  if (!s.units_row.empty()) f << s.units_row << "\r\n";
  std::uint64_t state = 12345;
  char buf[64];
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double j = s.jitter * jitter_unit(state);
    if (i >= s.gap_at && i < s.gap_at + s.gap_rows) continue;
    double t = s.t0 + static_cast<double>(i) * dt + j;
    if (s.float32_time) t = static_cast<double>(static_cast<float>(t));
    if (s.iso_time) {
      const double in_minute = 50.0 + t;  // 23:59:50 + t, the next day from 60 s on (t < 70 s)
      const bool next_day = in_minute >= 60.0;
      std::snprintf(buf, sizeof buf, "2026-11-%sT%s:%0*.*f+01:00", next_day ? "26" : "25", next_day ? "00:00" : "23:59",
                    s.time_decimals + 3, s.time_decimals, next_day ? in_minute - 60.0 : in_minute);
    } else if (s.time_decimals > 0)
      std::snprintf(buf, sizeof buf, "%.*f", s.time_decimals, t);
    else
      std::snprintf(buf, sizeof buf, "%.17g", t);
    f << buf << s.delimiter;
    if (i >= s.nan_at && i < s.nan_at + s.nan_rows) {
      f << (i == s.nan_at ? "NaN" : "");
    } else {
      std::snprintf(buf, sizeof buf, "%.9g", x[i] * s.length_factor);
      f << buf;
    }
    if (!u.empty()) {
      std::snprintf(buf, sizeof buf, "%.9g", u[i]);
      f << s.delimiter << buf;
    }
    f << "\r\n";
  }
}

/// A 2-D C-order float64 .npy array of rows × columns.
inline void write_npy_2d(const std::string& path, const std::vector<std::vector<double>>& columns) {
  const std::size_t rows = columns.front().size(), cols = columns.size();
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", " +
                       std::to_string(cols) + "), }";
  header.append(64 - (10 + header.size() + 1) % 64, ' ');
  header += '\n';
  std::ofstream f(path, std::ios::binary);
  f.write("\x93NUMPY\x01\x00", 8);
  const unsigned char len[2] = {static_cast<unsigned char>(header.size() & 0xff),
                                static_cast<unsigned char>(header.size() >> 8)};
  f.write(reinterpret_cast<const char*>(len), 2);
  f << header;
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) f.write(reinterpret_cast<const char*>(&columns[c][r]), 8);
}

/// A MATLAB v4 .mat file with one full double matrix per variable (little-endian, column-major).
struct MatVariable {
  std::string name;
  std::size_t rows = 0, cols = 0;
  std::vector<double> column_major;
};
inline void write_mat_v4(const std::string& path, const std::vector<MatVariable>& vars) {
  std::ofstream f(path, std::ios::binary);
  for (const auto& v : vars) {
    const std::int32_t head[5] = {0, static_cast<std::int32_t>(v.rows), static_cast<std::int32_t>(v.cols), 0,
                                  static_cast<std::int32_t>(v.name.size() + 1)};
    f.write(reinterpret_cast<const char*>(head), sizeof head);
    f.write(v.name.c_str(), static_cast<std::streamsize>(v.name.size() + 1));
    f.write(reinterpret_cast<const char*>(v.column_major.data()),
            static_cast<std::streamsize>(8 * v.column_major.size()));
  }
}

}  // namespace vehs::test
