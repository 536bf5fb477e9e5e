// Isolated glitch samples (vehs/core/glitches.hpp): found exactly, never on clean records, and
// dropped by cutting the record.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "oscillator_records.hpp"
#include "vehs/core/glitches.hpp"

using core_test::oscillator;

TEST_CASE("one displaced sample is found at its line, with nothing else", "[core][glitches][asan]") {
  vehs::Dataset d = oscillator(20000, 11, 2);
  const std::size_t at = 7777;
  d.x[d.records[1].offset + at] = 0.5 + d.x[d.records[1].offset + at];  // the glitch: one x off by 0.5
  const auto g = vehs::find_glitches(d);
  REQUIRE(g.size() == 1);
  CHECK(g[0].record == 1);
  CHECK(g[0].sample == at);
  CHECK(g[0].line == d.records[1].first_line + at);
  CHECK(g[0].score > 100.0);
  CHECK(vehs::describe_glitches(d, g).find("clean.csv: line " + std::to_string(g[0].line)) == 0);
}

TEST_CASE("clean records have no glitches (false alarm per run < 1e-20)", "[core][glitches]") {
  // r_i is close to Gaussian here (additive noise): per sample 2*Phi(-12) = 3.6e-33, times 2e5
  // samples and the slack of the MAD estimate, far below 1e-4 per run.
  for (std::uint32_t seed = 1; seed <= 10; ++seed) CHECK(vehs::find_glitches(oscillator(20000, seed)).empty());
}

TEST_CASE("a steep smooth feature is not a glitch - two adjacent bad samples are not isolated", "[core][glitches]") {
  vehs::Dataset d = oscillator(5000, 3);
  // a step (an offset jump) changes r at two samples with the same magnitude: not the signature
  for (std::size_t i = 2500; i < d.x.size(); ++i) d.x[i] += 2.0;
  CHECK(vehs::find_glitches(d).empty());
}

TEST_CASE("drop_glitches cuts the record around each glitch", "[core][glitches][asan]") {
  vehs::Dataset d = oscillator(1000, 5);
  d.x[300] += 1.0;
  d.x[310] -= 1.0;
  const auto g = vehs::find_glitches(d);
  REQUIRE(g.size() == 2);
  const vehs::Dataset kept = vehs::drop_glitches(d, g, 16);
  REQUIRE(kept.records.size() == 2);  // [0, 300) and [311, 1000); the 9 samples between are too few
  CHECK(kept.records[0].size == 300);
  CHECK(kept.records[1].size == 689);
  CHECK(kept.records[1].first_line == d.records[0].first_line + 311);
  CHECK(kept.records[1].t0 == Approx(3.11));
  CHECK(kept.x[300] == d.x[311]);
  CHECK(vehs::find_glitches(kept).empty());
}

TEST_CASE("values printed with 2 or 3 decimals: rounding steps are not glitches, a real one still is",
          "[core][glitches]") {
  // a second outside tester's "%.2f"/"%.3f" files stopped with "glitches" of 1e12-1e14 robust sd:
  // most r_i were exactly 0 and the MAD was round-off
  for (const double q : {0.01, 0.001})
    for (const double dt : {0.01, 0.002}) {
      vehs::Dataset d = oscillator(20000, 31, 2, dt);
      for (double& x : d.x) x = q * std::round(x / q);
      INFO("q " << q << ", dt " << dt);
      CHECK(vehs::find_glitches(d).empty());
      const std::size_t at = d.records[1].offset + 5000;
      d.x[at] += 50.0 * q;  // 50 steps off: 141 rounding sd of r
      const auto g = vehs::find_glitches(d);
      REQUIRE(g.size() == 1);
      CHECK(g[0].sample == 5000);
    }
}

TEST_CASE("a bad first or last sample of a record is a glitch (the one-sided rule at the ends)",
          "[core][glitches][asan]") {
  // a logger killed mid-write ("3,49.99,0." read as x = 0) or a 0 logged at a record's start
  // wrecked the fit unseen: the ends had no test
  const vehs::Dataset clean = oscillator(5000, 17, 3);
  for (const std::size_t at : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{4997}, std::size_t{4998},
                               std::size_t{4999}})
    for (const double bad : {0.0, 3.0}) {
      vehs::Dataset d = clean;
      const std::size_t k = d.records[1].offset + at;
      if (std::abs(d.x[k] - bad) < 0.2) continue;  // not off its neighbours
      d.x[k] = bad;
      INFO("sample " << at << " set to " << bad);
      const auto g = vehs::find_glitches(d);
      REQUIRE(g.size() == 1);
      CHECK(g[0].record == 1);
      CHECK(g[0].sample == at);
      CHECK(g[0].line == d.records[1].first_line + at);
      const vehs::Dataset kept = vehs::drop_glitches(d, g);
      CHECK(vehs::find_glitches(kept).empty());
      const std::size_t after = 4999 - at, stub = (at < 16 ? at : 0) + (after < 16 ? after : 0);
      CHECK(kept.total_samples() == d.total_samples() - 1 - stub);  // (the pieces under 16 samples go too)
    }
}

TEST_CASE("clean records: no glitch at their ends either - nor a step at the second sample", "[core][glitches]") {
  for (std::uint32_t seed = 1; seed <= 10; ++seed) CHECK(vehs::find_glitches(oscillator(2000, seed, 4)).empty());
  vehs::Dataset d = oscillator(2000, 3);
  for (std::size_t i = 2; i < d.x.size(); ++i) d.x[i] += 2.0;  // an offset jump between samples 1 and 2
  CHECK(vehs::find_glitches(d).empty());
}
