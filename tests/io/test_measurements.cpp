#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"

namespace fs = std::filesystem;

namespace {
std::string temp(const std::string& name, const std::string& text = "") {
  const auto p = fs::temp_directory_path() / name;
  if (!text.empty()) std::ofstream(p) << text;
  return p.string();
}

vehs::Dataset two_records() {
  vehs::Dataset d;
  for (long long id : {3, 7}) {
    vehs::Record r;
    r.id = id;
    r.t0 = 1.0;
    r.dt = 0.001;
    r.offset = d.x.size();
    r.size = 1000;
    for (std::size_t i = 0; i < r.size; ++i) {
      d.x.push_back(std::sin(0.01 * static_cast<double>(i) + static_cast<double>(id)) / 3.0);
      d.y.push_back(std::cos(0.1 * static_cast<double>(i)));
    }
    d.records.push_back(r);
  }
  return d;
}
}  // namespace

TEST_CASE("CSV and .npy measurement files round-trip exactly", "[io]") {
  const auto d = two_records();
  for (const char* ext : {".csv", ".npy"}) {
    CAPTURE(ext);
    const auto p = temp(std::string("vehs_rt") + ext);
    vehs::write_measurements(p, d, {});
    vehs::ReadOptions o;
    o.read_y = true;
    const auto back = vehs::read_measurements(p, o);
    REQUIRE(back.records.size() == 2);
    CHECK(back.records[1].id == 7);
    CHECK(back.records[1].size == 1000);
    CHECK(back.records[0].dt == Approx(0.001).epsilon(1e-12));
    CHECK(back.records[0].t0 == 1.0);
    CHECK(back.x == d.x);
    CHECK(back.y == d.y);
  }
}

TEST_CASE("CSV quirks: quoted headers, trailing commas, free column order, no time column", "[io]") {
  const auto p = temp("vehs_quirks.csv", "\"V1\",\"V2\",\n0.5,1.5,\n0.25,-2e-3,\n0.125,3,\n");
  vehs::ReadOptions o;
  o.x_column = "V2";
  o.u_column = "V1";
  o.dt = 0.5;
  const auto d = vehs::read_measurements(p, o);
  REQUIRE(d.records.size() == 1);
  CHECK(d.x == std::vector<double>{1.5, -2e-3, 3});
  CHECK(d.u == std::vector<double>{0.5, 0.25, 0.125});
  CHECK(d.records[0].dt == 0.5);
  const auto q = temp("vehs_order.csv", "x,t\n1,0\n2,0.1\n3,0.2\n");
  CHECK(vehs::read_measurements(q).records[0].dt == Approx(0.1));
}

TEST_CASE("European and spreadsheet CSV: decimal commas with semicolons, '%' comments, NA / #N/A as missing",
          "[io]") {
  // a new user's logger files (25 Nov 2026) stopped at "'0,000000' is not a number", "no column
  // 'x' (columns: % logger v1)" and "'NA' is not a number"
  std::string text = "% logger v1\n% channel 1: mm\nt;x\n";
  for (int i = 0; i < 40; ++i) {
    char row[64];
    std::snprintf(row, sizeof row, "%d,%02d;%s\n", i / 100, i % 100, i == 20 ? "#N/A" : i == 21 ? "NA" : "0,5");
    text += row;
  }
  vehs::ReadOptions o;
  o.min_samples = 16;
  vehs::ReadSummary summary;
  const auto d = vehs::read_measurements(temp("vehs_euro.csv", text), o, &summary);
  REQUIRE(d.records.size() == 2);  // split at the two missing values
  CHECK(d.records[0].size == 20);
  CHECK(d.records[1].size == 18);
  CHECK(d.records[0].dt == Approx(0.01));
  CHECK(d.x[0] == 0.5);
  // a delimiter inside double quotes does not split the field (a comment column, a quoted number)
  const auto q = vehs::read_measurements(
      temp("vehs_quoted.csv", "t,x,note\n0,1,\"a, b\"\n0.1,2,\"c\"\n0.2,3,\n0.3,4,\"1,234.5\"\n"));
  CHECK(q.x == std::vector<double>{1, 2, 3, 4});
  // with ',' as the delimiter a comma is never a decimal point
  CHECK_THROWS_WITH(vehs::read_measurements(temp("vehs_comma.csv", "t,x\n0,1,5\n0.1,2\n"), o),
                    Catch::Contains("has 3 fields"));
}

TEST_CASE("bad measurement files give one-line errors naming file, record and line", "[io]") {
  auto err = [](const std::string& name, const std::string& text, vehs::GapPolicy gaps = vehs::GapPolicy::Split) {
    const auto p = temp(name, text);
    try {
      vehs::ReadOptions o;
      o.on_gap = gaps;
      vehs::read_measurements(p, o);
    } catch (const vehs::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(err("b1.csv", "t,x\n0,1\n0.1,2\n0.22,3\n0.3,4\n"),  // a step 20 % off
             Catch::Contains("b1.csv: line 4") && Catch::Contains("non-uniform"));
  CHECK_THAT(err("b2.csv", "traj,t,x\n1,0,1\n1,0.1,nan\n", vehs::GapPolicy::Fail),
             Catch::Contains("b2.csv: line 3 (record traj=1)") && Catch::Contains("NaN"));
  CHECK_THAT(err("b3.csv", "t,x\n0,1\n0.1,abc\n"), Catch::Contains("line 3") && Catch::Contains("not a number"));
  CHECK_THAT(err("b4.csv", "t,y\n0,1\n"), Catch::Contains("no column 'x'"));
  CHECK_THAT(err("b5.csv", "traj,t,x\n1,0,1\n1,0.1,1\n2,0,1\n2,0.1,1\n1,0.2,1\n1,0.3,1\n"),
             Catch::Contains("appears again"));
  CHECK_THAT(err("b6.csv", "t,x\n0,1\n"), Catch::Contains("only 1 samples"));
  CHECK_THAT(err("b7.csv", "t,x\n0,1\n0,2\n"), Catch::Contains("does not increase"));
  CHECK_THAT(err("b8.csv", ""), Catch::Contains("cannot open") || Catch::Contains("empty"));
  CHECK_THAT(err("b9.csv", "t,x\n0,1\n0.1\n"), Catch::Contains("line 3: has 1 fields"));
  // a new user's logger files (25 Nov): extra non-empty fields (a shifted row), a record at
  // another interval in the same file (was: cut into single samples and dropped, exit 0),
  // classic-Mac line ends (was: a 600 kB message), UTF-16, an .npz archive
  CHECK_THAT(err("b10.csv", "t,x\n0,1\n0.1,2,7\n0.2,3\n"), Catch::Contains("line 3: has 3 fields, the header 2"));
  std::string mixed = "traj,t,x\n";
  for (int i = 0; i < 20; ++i) mixed += "0," + std::to_string(0.01 * i) + "," + std::to_string(std::sin(i)) + "\n";
  for (int i = 0; i < 20; ++i) mixed += "1," + std::to_string(0.02 * i) + "," + std::to_string(std::sin(i)) + "\n";
  CHECK_THAT(err("b11.csv", mixed), Catch::Contains("b11.csv: line 23 (record traj=1)") &&
                                        Catch::Contains("sampling interval changes from 0.01 to 0.02"));
  CHECK_THAT(err("b12.csv", "t,x\r0,1\r0.1,2\r0.2,3\r"), Catch::Contains("'\\r' alone"));
  CHECK_THAT(err("b13.csv", std::string("\xFF\xFEt\0,\0x\0\n\0", 10)), Catch::Contains("UTF-16"));
  CHECK_THAT(err("b14.npz", "PK\x03\x04"), Catch::Contains("b14.npz: .npz files are not read"));
  // the interval halves (or doubles) inside one record: the line of the first step at the new
  // interval (was, halving: "non-uniform sampling" at an earlier line, 0.05 against the mean)
  for (const double factor : {0.5, 2.0}) {
    std::string changed = "t,x\n";
    double t = 0.0;
    for (int i = 0; i < 80; ++i, t += i < 40 ? 0.05 : 0.05 * factor)
      changed += std::to_string(t) + "," + std::to_string(std::sin(i)) + "\n";
    CHECK_THAT(err("b16.csv", changed), Catch::Contains("b16.csv: line 42: the sampling interval changes from 0.05 to " +
                                                        std::string(factor < 1.0 ? "0.025" : "0.1")));
  }
  // a NUL inside a value is shown escaped (was: the message ended at the NUL)
  CHECK_THAT(err("b17.csv", std::string("t,x\n0,1\n0.1,2\0\n0.2,3\n", 21)),
             Catch::EndsWith("b17.csv: line 3: column 'x': '2\\x00' is not a number"));
  // trailing empty fields (Silverbox's "V1,V2,") stay fine
  CHECK(err("b15.csv", "t,x,\n0,1,\n0.1,2,,\n0.2,3,\n").find("no error") == 0);
}
