// Flat stretches (vehs/core/flat_stretches.hpp): a dropout logged as 0 and a stuck sensor found
// at their lines; none on clean float records or on integer counts sampled fast (quantised data
// repeat values all the time); dropped by cutting the record.
#include <catch2/catch.hpp>

#include <cmath>

#include "oscillator_records.hpp"
#include "vehs/core/flat_stretches.hpp"

using core_test::oscillator;
using core_test::oscillator_counts;

TEST_CASE("a dropout logged as 0 and a stuck reading are found at their lines", "[core][flat_stretches][asan]") {
  vehs::Dataset d = oscillator(4000, 21, 3);
  const vehs::Record& r1 = d.records[1];
  for (std::size_t i = 2000; i < 2050; ++i) d.x[r1.offset + i] = 0.0;  // 50 samples of 0
  const vehs::Record& r2 = d.records[2];
  for (std::size_t i = 901; i < 921; ++i) d.x[r2.offset + i] = d.x[r2.offset + 900];  // stuck for 20 more
  const auto f = vehs::find_flat_stretches(d);
  REQUIRE(f.size() == 2);
  CHECK(f[0].record == 1);
  CHECK(f[0].sample == 2000);
  CHECK(f[0].length == 50);
  CHECK(f[0].line == r1.first_line + 2000);
  CHECK(f[0].x == 0.0);
  CHECK(f[1].record == 2);
  CHECK(f[1].sample == 900);
  CHECK(f[1].length == 21);
  const std::string text = vehs::describe_flat_stretches(d, f);
  CHECK(text.find("clean.csv: lines " + std::to_string(r1.first_line + 2000) + "-" +
                  std::to_string(r1.first_line + 2049) + " (50 samples of x = 0)") == 0);
}

TEST_CASE("clean float records and fast integer counts have no flat stretches", "[core][flat_stretches]") {
  // floats: an exact repeat of a double needs a zero increment (no run of 5 in 10 x 20 000
  // samples); counts: round(100 x) at dt 0.001 repeats ~90 % of consecutive samples, runs at the
  // turning points last up to ~100 samples and the bar is ~290 (N p^(L-1) = 1e-9).
  for (std::uint32_t seed = 1; seed <= 10; ++seed) CHECK(vehs::find_flat_stretches(oscillator(20000, seed)).empty());
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    vehs::Dataset d = oscillator(20000, seed, 1, 0.001);
    std::size_t equal = 0;
    for (double& x : d.x) x = std::round(100.0 * x);
    for (std::size_t i = 1; i < d.x.size(); ++i) equal += d.x[i] == d.x[i - 1];
    INFO("share of equal consecutive counts " << double(equal) / double(d.x.size() - 1));
    CHECK(double(equal) / double(d.x.size() - 1) > 0.7);
    CHECK(vehs::find_flat_stretches(d).empty());
  }
}

TEST_CASE("quantised records are not checked: ADC counts and short printouts repeat at the turning "
          "points", "[core][flat_stretches]") {
  // a new user's 10-16-bit records at 1-20 kHz and values printed with 2-3 decimals stopped with
  // false alarms under the record-wide rule (runs of 10-400 samples at the turning points)
  for (const double dt : {0.001, 0.0002})
    for (const double resolution : {1e-2, 1e-3, 1e-4}) {
      vehs::Dataset d = oscillator(20000, 17, 2, dt);
      for (double& x : d.x) x = resolution * std::round(x / resolution);
      INFO("dt " << dt << ", resolution " << resolution);
      CHECK(vehs::find_flat_stretches(d).empty());
    }
}

TEST_CASE("drop_flat_stretches cuts the record around each stretch", "[core][flat_stretches][asan]") {
  vehs::Dataset d = oscillator(1000, 5);
  for (std::size_t i = 300; i < 310; ++i) d.x[i] = 0.0;
  const auto f = vehs::find_flat_stretches(d);
  REQUIRE(f.size() == 1);
  const vehs::Dataset kept = vehs::drop_flat_stretches(d, f, 16);
  REQUIRE(kept.records.size() == 2);  // [0, 300) and [310, 1000)
  CHECK(kept.records[0].size == 300);
  CHECK(kept.records[1].size == 690);
  CHECK(kept.records[1].first_line == d.records[0].first_line + 310);
  CHECK(kept.records[1].t0 == Approx(3.10));
  CHECK(kept.x[300] == d.x[310]);
  CHECK(vehs::find_flat_stretches(kept).empty());
}

TEST_CASE("a clipped quantised record: every run at the piled-up extreme is flagged",
          "[core][flat_stretches]") {
  // a second outside tester's 10-bit Duffing at 20 kHz clipped at ±81 counts (0.9 % of the
  // samples, runs up to 192, shorter than the record's natural runs): not seen before. Here
  // 2 records of 40 time units (about 6 periods each), counts round(100 x) at dt 0.0002 (most
  // consecutive samples equal: quantised) clipped at 80 % of the largest count.
  vehs::Dataset d = oscillator_counts(200000, 23, 2, 0.0002, 100.0);
  double top = 0.0;
  for (double x : d.x) top = std::max(top, x);
  const double clip = std::round(0.8 * top);
  std::size_t clipped = 0;
  for (double& x : d.x)
    if (x >= clip) x = clip, ++clipped;
  const auto flat = vehs::find_flat_stretches(d);
  INFO("clip " << clip << ", clipped samples " << clipped);
  REQUIRE(!flat.empty());
  std::size_t covered = 0;
  for (const auto& f : flat) {
    CHECK(f.clipped);
    CHECK(f.x == clip);
    covered += f.length;
  }
  // a record is flagged when it visits its extreme in at least 3 runs: here one record holds
  // 7238 of the 8218 clipped samples, the other (fewer visits) is not flagged
  CHECK(covered <= clipped);
  CHECK(double(covered) >= 0.8 * double(clipped));
  CHECK(vehs::describe_flat_stretches(d, flat).find("clipped?") != std::string::npos);
}

namespace {

/// `data` with samples [from, from + length) of record `record` set to `value`.
vehs::Dataset with_run(vehs::Dataset data, std::size_t record, std::size_t from, std::size_t length, double value) {
  const vehs::Record& r = data.records[record];
  for (std::size_t i = from; i < from + length; ++i) data.x[r.offset + i] = value;
  return data;
}

/// Exactly one stretch, at `sample` of `record`, `length` samples long (a held reading's run
/// includes its last good sample, before the planted ones).
void check_one(const std::vector<vehs::FlatStretch>& found, std::size_t record, std::size_t sample, std::size_t length) {
  REQUIRE(found.size() == 1);
  CHECK(found[0].record == record);
  CHECK(found[0].sample == sample);
  CHECK(found[0].length == length);
}

}  // namespace

TEST_CASE("a dropout and a held reading in a quantised record: runs entered or left by a jump",
          "[core][flat_stretches]") {
  // an outside check: 50 samples logged as 0, or held at the last reading, in a 12-bit bistable
  // at 20 kHz gave beta 11 039 for 6.28 (and +41 %) with exit 0 (quantised records were checked
  // for clipping only). Here counts round(1000 x) at dt 0.002: increments of 0-3 counts, repeats
  // in short runs and in runs of up to ~100 samples at the turning points.
  vehs::Dataset d = oscillator_counts(100000, 29, 2, 0.002, 1000.0);
  REQUIRE(vehs::find_flat_stretches(d).empty());
  // where the signal moves: the largest increment of record 0 in its second half
  const vehs::Record& r0 = d.records[0];
  const double* x0 = d.x_of(r0);
  std::size_t moving = 50000;
  for (std::size_t i = 50000; i + 1 < 90000; ++i)
    if (std::abs(x0[i + 1] - x0[i]) > std::abs(x0[moving + 1] - x0[moving])) moving = i;
  INFO("moving at sample " << moving << ", x " << x0[moving] << ", step " << x0[moving + 1] - x0[moving]);
  REQUIRE(std::abs(x0[moving]) > 100.0);  // 0 is a jump away
  const auto fz = vehs::find_flat_stretches(with_run(d, 0, moving, 50, 0.0));
  check_one(fz, 0, moving, 50);
  CHECK(fz[0].x == 0.0);
  CHECK_FALSE(fz[0].clipped);
  check_one(vehs::find_flat_stretches(with_run(d, 0, moving + 1, 49, x0[moving])), 0, moving, 50);
}

TEST_CASE("a noise-free ADC sampled far faster than the signal moves: no false alarm, a dropout found",
          "[core][flat_stretches]") {
  // round(1000 x) at dt 0.0002: increments of at most one count, every repeat in a long run (up to
  // ~600 samples at the turning points; the share of repeats in short runs is below 1e-3, so the
  // record-wide run-length rule used to flag them: an outside tester's noise-free 10-bit record at
  // 20 kHz, a 481-sample run). Most pairs are equal: the record is read as quantised.
  vehs::Dataset d = oscillator_counts(100000, 29, 2, 0.0002, 1000.0);
  CHECK(vehs::find_flat_stretches(d).empty());
  const double* x1 = d.x_of(d.records[1]);
  std::size_t far = 20000;  // a sample well away from 0
  while (std::abs(x1[far]) < 200.0) ++far;
  check_one(vehs::find_flat_stretches(with_run(d, 1, far, 30, 0.0)), 1, far, 30);
}
