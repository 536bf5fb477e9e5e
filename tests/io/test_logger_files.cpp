// The readers on files written the way loggers write them (logger_files.hpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "vehs/io/detail/iso_time.hpp"
#include "io/logger_files.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"

namespace fs = std::filesystem;

namespace {

std::string temp(const std::string& name) { return (fs::temp_directory_path() / name).string(); }

/// 3000 samples of a 300 Hz logger: a decaying two-tone displacement in m, a drive.
constexpr double kDt = 1.0 / 300.0;
std::vector<double> displacement(std::size_t n = 3000) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * kDt;
    x[i] = 2e-3 * std::sin(2 * M_PI * 7.0 * t) + 5e-4 * std::cos(2 * M_PI * 31.0 * t);
  }
  return x;
}
std::vector<double> drive(std::size_t n = 3000) {
  std::vector<double> u(n);
  for (std::size_t i = 0; i < n; ++i) u[i] = 0.3 * std::sin(0.05 * static_cast<double>(i));
  return u;
}

vehs::ReadOptions logger_columns() {
  vehs::ReadOptions o;
  o.t_column = "time [s]";
  o.x_column = "disp [mm]";
  o.u_column = "acc [m/s^2]";
  return o;
}

std::string error_of(const std::string& path, const vehs::ReadOptions& o) {
  try {
    vehs::read_measurements(path, o);
  } catch (const vehs::Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("a logger CSV: BOM, comments, semicolons, quoted names, 6-decimal stamps with 0.2 ms jitter, mm", "[io][logger]") {
  const auto x = displacement(), u = drive();
  vehs::test::LoggerStyle s;
  s.jitter = 2e-4;
  s.length_factor = 1000.0;
  const auto p = temp("vehs_logger.csv");
  vehs::test::write_logger_csv(p, x, u, kDt, s);
  vehs::ReadSummary summary;
  const auto d = vehs::read_measurements(p, logger_columns(), &summary);
  REQUIRE(d.records.size() == 1);
  CHECK(d.records[0].size == x.size());
  CHECK(d.records[0].first_line == 5);  // 3 comment lines, the header, then data
  // the mean interval of 3000 stamps with ±0.2 ms jitter: within 2·0.2 ms / 2999 of 1/300
  CHECK(std::abs(d.records[0].dt - kDt) < 4e-4 / 2999.0);
  CHECK(d.x[100] == Approx(1000.0 * x[100]).margin(1e-6));
  CHECK(d.u[100] == Approx(u[100]).margin(1e-8));
  // ±0.2 ms stamps move a 3.33 ms step by up to 12 %: accepted, with a warning naming the file
  REQUIRE(summary.warnings.size() == 1);
  CHECK_THAT(summary.warnings[0], Catch::Contains("vehs_logger.csv") && Catch::Contains("jitter_tolerance"));
  CHECK(summary.max_jitter > 0.05);
  CHECK(summary.max_jitter < 0.13);
  // tighter than the data: an error naming the line of the worst step
  vehs::ReadOptions tight = logger_columns();
  tight.jitter_tolerance = 0.01;
  CHECK_THAT(error_of(p, tight), Catch::Contains("vehs_logger.csv: line ") && Catch::Contains("non-uniform sampling"));
}

TEST_CASE("logged time stamps: 6 decimals, float32, 10 significant digits - dt given checks the column", "[io][logger]") {
  const auto x = displacement();
  for (int variant = 0; variant < 3; ++variant) {
    CAPTURE(variant);
    vehs::test::LoggerStyle s;
    s.t0 = 12.5;  // a logger's clock does not start at 0
    if (variant == 1) s.float32_time = true, s.time_decimals = 0;
    if (variant == 2) s.time_decimals = 0, s.t0 = 1234.567891;  // full digits, large offset
    const auto p = temp("vehs_stamps.csv");
    vehs::test::write_logger_csv(p, x, {}, kDt, s);
    vehs::ReadSummary summary;
    auto o = logger_columns();
    const auto d = vehs::read_measurements(p, o, &summary);
    REQUIRE(d.records.size() == 1);
    CHECK(d.records[0].dt == Approx(kDt).epsilon(1e-6));
    CHECK(summary.max_jitter < 0.01);
    o.dt = kDt;  // given: the column is only checked, the record gets exactly dt
    CHECK(vehs::read_measurements(p, o).records[0].dt == kDt);
    o.dt = 1.05 * kDt;
    CHECK_THAT(error_of(p, o), Catch::Contains("given dt"));
  }
}

TEST_CASE("a gap and a NaN run split a record (counted) or fail naming the line", "[io][logger]") {
  const auto x = displacement(), u = drive();
  vehs::test::LoggerStyle s;
  s.gap_at = 1000, s.gap_rows = 40;   // 40 samples lost
  s.nan_at = 2000, s.nan_rows = 5;    // "NaN" then 4 empty fields
  const auto p = temp("vehs_gaps.csv");
  vehs::test::write_logger_csv(p, x, u, kDt, s);
  vehs::ReadSummary summary;
  const auto d = vehs::read_measurements(p, logger_columns(), &summary);
  REQUIRE(d.records.size() == 3);
  CHECK(summary.gaps == 1);
  CHECK(summary.missing_runs == 1);
  CHECK(summary.missing_rows == 5);
  CHECK(d.records[0].size == 1000);
  CHECK(d.records[1].size == 960);
  CHECK(d.records[2].size == 3000 - 2005);
  CHECK(d.records[1].t0 == Approx(1040 * kDt).margin(1e-6));
  CHECK(d.x[d.records[2].offset] == Approx(x[2005]).margin(1e-11));
  CHECK(d.u.size() == d.x.size());
  for (const auto& r : d.records) CHECK(r.dt == Approx(kDt).epsilon(1e-6));
  // stamps with 6 decimals at 300 Hz: steps 3e-4 off (a warning above 1e-4), then the split
  REQUIRE(summary.warnings.size() == 2);
  CHECK_THAT(summary.warnings[0], Catch::Contains("time steps deviate"));
  CHECK_THAT(summary.warnings[1], Catch::Contains("1 time gap(s)") && Catch::Contains("1 run(s) of missing values"));
  auto fail = logger_columns();
  fail.on_gap = vehs::GapPolicy::Fail;
  CHECK_THAT(error_of(p, fail), Catch::Contains("vehs_gaps.csv: line 1005") && Catch::Contains("gap"));
  s.gap_rows = 0;
  vehs::test::write_logger_csv(p, x, u, kDt, s);
  CHECK_THAT(error_of(p, fail), Catch::Contains("vehs_gaps.csv: line 2005") && Catch::Contains("'disp [mm]'") &&
                                    Catch::Contains("NaN"));
  // a NaN run near the start leaves a piece shorter than min_samples: dropped and counted
  s.nan_at = 10;
  vehs::test::write_logger_csv(p, x, u, kDt, s);
  auto o = logger_columns();
  o.min_samples = 16;
  vehs::ReadSummary short_piece;
  const auto e = vehs::read_measurements(p, o, &short_piece);
  CHECK(e.records.size() == 1);
  CHECK(short_piece.dropped_pieces == 1);
  CHECK(short_piece.dropped_samples == 10);
}

TEST_CASE("delimiters, duplicate names, comment lines between rows", "[io][logger]") {
  const auto p = temp("vehs_tabs.csv");
  std::ofstream(p) << "# exported\n't'\t'x'\n0\t1\n# pause marker\n0.5\t2\n\n1.0\t3\n";
  vehs::ReadOptions o;
  const auto d = vehs::read_measurements(p, o);
  CHECK(d.x == std::vector<double>{1, 2, 3});
  CHECK(d.records[0].dt == 0.5);
  // ';' comment lines (INI-style loggers): before the header, and between rows when ';' is not
  // the delimiter; with ';' as the delimiter a leading ';' is an empty first field
  const auto c = temp("vehs_semicolon_comments.csv");
  std::ofstream(c) << "; Logger v2\n; rate 2 Hz\nt,x\n0,1\n; marker\n0.5,2\n1.0,3\n";
  CHECK(vehs::read_measurements(c, o).x == std::vector<double>{1, 2, 3});
  const auto e = temp("vehs_semicolon_empty.csv");
  std::ofstream(e) << "; Logger v2\nt;x\n0;1\n;2\n";
  CHECK_THAT(error_of(e, o), Catch::Contains("vehs_semicolon_empty.csv") && Catch::Contains("line 4"));
  const auto q = temp("vehs_dup.csv");
  std::ofstream(q) << "t;x;x\n0;1;2\n";
  CHECK_THAT(error_of(q, o), Catch::Contains("vehs_dup.csv") && Catch::Contains("'x' appears twice"));
}

TEST_CASE("2-D .npy and MATLAB .mat files read with a column mapping", "[io][logger]") {
  const auto x = displacement(500), u = drive(500);
  std::vector<double> t(500);
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = 3.0 + static_cast<double>(i) * kDt;
  vehs::ReadOptions o;
  o.columns = {"t", "", "x", "u"};
  const auto n = temp("vehs_2d.npy");
  vehs::test::write_npy_2d(n, {t, std::vector<double>(500, 9.0), x, u});
  const auto d = vehs::read_measurements(n, o);
  REQUIRE(d.records.size() == 1);
  CHECK(d.x == x);
  CHECK(d.u == u);
  CHECK(d.records[0].t0 == 3.0);
  CHECK(d.records[0].dt == Approx(kDt).epsilon(1e-12));
  o.columns = {"t", "x"};
  CHECK_THAT(error_of(n, o), Catch::Contains("4 columns") && Catch::Contains("'columns'"));

  // vectors named like the columns
  const auto m = temp("vehs_vectors.mat");
  vehs::test::write_mat_v4(m, {{"t", 500, 1, t}, {"x", 1, 500, x}, {"notes", 1, 2, {1, 2}}});
  vehs::ReadOptions mo;
  const auto e = vehs::read_measurements(m, mo);
  REQUIRE(e.records.size() == 1);
  CHECK(e.x == x);
  CHECK(e.records[0].dt == Approx(kDt).epsilon(1e-12));
  // one matrix with named columns
  std::vector<double> cm = t;
  cm.insert(cm.end(), x.begin(), x.end());
  const auto k = temp("vehs_matrix.mat");
  vehs::test::write_mat_v4(k, {{"rec", 500, 2, cm}});
  vehs::ReadOptions ko;
  ko.mat_variable = "rec";
  ko.columns = {"t", "x"};
  CHECK(vehs::read_measurements(k, ko).x == x);
  ko.mat_variable = "nope";
  CHECK_THAT(error_of(k, ko), Catch::Contains("vehs_matrix.mat") && Catch::Contains("'nope'"));
}

TEST_CASE("ISO-8601 time stamps (crossing midnight, with an offset) and a row of units under the header",
          "[io][logger]") {
  const auto x = displacement(), u = drive();
  vehs::test::LoggerStyle s;
  s.iso_time = true;
  s.time_decimals = 4;
  s.units_row = "s;mm;m/s^2";
  const auto p = temp("vehs_logger_iso.csv");
  vehs::test::write_logger_csv(p, x, u, kDt, s);
  vehs::ReadSummary summary;
  const auto d = vehs::read_measurements(p, logger_columns(), &summary);
  REQUIRE(d.records.size() == 1);
  CHECK(d.records[0].size == x.size());
  CHECK(d.records[0].first_line == 6);  // 3 comment lines, the header, the units, then data
  CHECK(d.records[0].t0 == 0.0);        // seconds since the file's first stamp
  // 4-decimal stamps of a 1/300 s step: each within 0.05 ms, the mean over 2999 steps within 1e-7 / 2999
  CHECK(std::abs(d.records[0].dt - kDt) < 1e-4 / 2999.0);
  CHECK(d.x[100] == Approx(x[100]).margin(1e-9));
  CHECK(d.u[100] == Approx(u[100]).margin(1e-8));
  REQUIRE(!summary.warnings.empty());
  CHECK_THAT(summary.warnings[0], Catch::Contains("line 5 read as a row of units"));
}

TEST_CASE("ISO-8601 stamps: exact seconds, offsets, impossible dates refused", "[io][logger][asan]") {
  using vehs::io_detail::parse_iso8601;
  REQUIRE(parse_iso8601("1970-01-01T00:00:00Z"));
  CHECK(parse_iso8601("1970-01-01T00:00:00Z")->seconds == 0);
  const auto leap = parse_iso8601("2000-02-29 12:00:00.5+02:00");  // 10:00 UTC
  REQUIRE(leap);
  CHECK(leap->seconds == 951818400);
  CHECK(leap->fraction == 0.5);
  CHECK(parse_iso8601("2026-11-25T07:00:00,125")->fraction == Approx(0.125));
  CHECK(parse_iso8601("2026-11-25T07:00:00-0530")->seconds - parse_iso8601("2026-11-25T07:00:00Z")->seconds == 19800);
  CHECK_FALSE(parse_iso8601("2001-02-29T00:00:00"));
  CHECK_FALSE(parse_iso8601("2026-13-01T00:00:00"));
  CHECK_FALSE(parse_iso8601("2026-11-25T24:00:00"));
  CHECK_FALSE(parse_iso8601("2026-11-25T07:00:00."));
  CHECK_FALSE(parse_iso8601("2026-11-25T07:00:00 UTC"));
  CHECK_FALSE(parse_iso8601("12.5"));
}
