#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "tools/config.hpp"
#include "vehs/core/error.hpp"

namespace fs = std::filesystem;

namespace {
vehs::tools::ConfigSchema schema() {
  return {"tool", "does things",
          {{"dt", "number", "sampling interval", ""},
           {"substeps", "integer", "internal steps", "1"},
           {"output", "string", "output path", "out.csv"}},
          ""};
}
std::string write_temp(const std::string& name, const std::string& text) {
  const auto p = fs::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p.string();
}
}  // namespace

TEST_CASE("configs reject unknown keys with a suggestion", "[config]") {
  const auto f = write_temp("vehs_cfg1.json", R"({"dt": 0.01, "substep": 3})");
  CHECK_THROWS_WITH(vehs::tools::Config::load(f, schema()),
                    Catch::Contains("unknown key 'substep'") && Catch::Contains("did you mean 'substeps'"));
}

TEST_CASE("configs name the file and key of a bad value", "[config]") {
  const auto f = write_temp("vehs_cfg2.json", R"({"dt": -1, "substeps": 2.5})");
  auto c = vehs::tools::Config::load(f, schema());
  CHECK_THROWS_WITH(c.positive("dt"), Catch::Contains("vehs_cfg2.json: 'dt' must be > 0"));
  CHECK_THROWS_WITH(c.integer("substeps"), Catch::Contains("'substeps' must be an integer"));
  const auto g = write_temp("vehs_cfg3.json", R"({"substeps": 2})");
  CHECK_THROWS_WITH(vehs::tools::Config::load(g, schema()), Catch::Contains("missing required key 'dt'"));
  const auto h = write_temp("vehs_cfg4.json", R"({"dt": 0.1,)");
  CHECK_THROWS_WITH(vehs::tools::Config::load(h, schema()), Catch::Contains("not valid JSON"));
}

TEST_CASE("set-overrides parse JSON or bare strings", "[config]") {
  const auto f = write_temp("vehs_cfg5.json", R"({"dt": 0.01})");
  auto c = vehs::tools::Config::load(f, schema());
  c.set_override("substeps=4", schema());
  c.set_override("output=a/b.csv", schema());
  CHECK(c.integer("substeps") == 4);
  CHECK(c.string("output") == "a/b.csv");
  CHECK_THROWS_AS(c.set_override("nope=1", schema()), vehs::Error);
}

TEST_CASE("paths with control characters are refused naming the key (a NUL cut them)", "[config]") {
  // "data.csv\u0000junk" was read as data.csv; "sim.npy\u0000.csv" wrote CSV text into sim.npy
  const auto f = write_temp("vehs_cfg_nul.json", R"({"dt": 1, "output": "sim.npy\u0000.csv"})");
  const auto c = vehs::tools::Config::load(f, schema());
  CHECK(c.string("output").size() == 12);
  CHECK_THROWS_WITH(c.path("output"), f + ": 'output': the path 'sim.npy\\x00.csv' contains the control character "
                                          "0x00 (NUL) at byte 8 (paths must not hold control characters)");
  const vehs::tools::Config list(nlohmann::json::parse(R"({"data": ["a.csv", "b\tc.csv"]})"), "cfg.json");
  CHECK_THROWS_WITH(list.path_list("data"), Catch::StartsWith("cfg.json: 'data': the path 'b\\x09c.csv'") &&
                                                Catch::Contains("0x09 (tab) at byte 2"));
  CHECK(vehs::tools::Config(nlohmann::json::parse(R"({"data": "é ü.csv"})"), "cfg.json").path_list("data").size() == 1);
}

TEST_CASE("integer keys are range-checked before they are narrowed", "[config][errors]") {
  // an outside trial: folds 4294967298 ran as 2, stride 4294967297 as 1 (wrapped modulo 2^32)
  const auto f = write_temp("vehs_cfg_ints.json",
                            R"({"dt": 0.1, "folds": 4294967298, "stride": 4294967297, "neg": -1, "half": 2.5,
                                "huge": 18446744073709551615, "big_float": 1e30, "ok": 7, "ok_float": 12.0})");
  const vehs::tools::Config c(nlohmann::json::parse(std::ifstream(f)), "cfg.json");
  CHECK_THROWS_WITH(c.int_at_least("folds", 1, 10),
                    Catch::Contains("cfg.json: 'folds' must be at most 2147483647 (got 4294967298)"));
  CHECK_THROWS_WITH(c.int_at_least("stride", 0, 0), Catch::Contains("'stride' must be at most 2147483647"));
  CHECK_THROWS_WITH(c.integer_at_least("neg", 0, 0), Catch::Contains("'neg' must be >= 0 (got -1)"));
  CHECK_THROWS_WITH(c.int_at_least("half", 1, 1), Catch::Contains("'half' must be an integer (got 2.5)"));
  // 2^64 - 1 read as a long long was -1
  CHECK_THROWS_WITH(c.integer("huge"), Catch::Contains("'huge' is too large"));
  CHECK_THROWS_WITH(c.integer_at_least("huge", 0, 0), Catch::Contains("'huge' is too large"));
  CHECK_THROWS_WITH(c.integer("big_float"), Catch::Contains("'big_float' is too large"));
  CHECK_THROWS_WITH(c.integer_in("ok", 1, 5, 1), Catch::Contains("'ok' must be at most 5 (got 7)"));
  CHECK(c.int_at_least("ok", 1, 1) == 7);
  CHECK(c.int_at_least("ok_float", 1, 1) == 12);
  CHECK(c.int_at_least("absent", 1, 3) == 3);
  CHECK(vehs::tools::json_integer(nlohmann::json::parse("9223372036854775807")) == 9223372036854775807LL);
  CHECK_FALSE(vehs::tools::json_integer(nlohmann::json::parse("9223372036854775808")));
  CHECK_FALSE(vehs::tools::json_integer(nlohmann::json(2.5)));
  CHECK_FALSE(vehs::tools::json_integer(nlohmann::json("3")));
}
