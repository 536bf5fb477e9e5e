// The model history file: versions numbered per data fingerprint, the model stored with its hash,
// scores and components kept, a foreign file rejected with a one-line error naming it.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "../diagnose/diagnose_fixtures.hpp"
#include "tools/history.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/model_file.hpp"

namespace fs = std::filesystem;
using namespace diag_test;

TEST_CASE("model history: versions per data fingerprint, model and score kept, bad files rejected",
          "[tools][history]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_history_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "history.json").string();
  DataSpec s;
  s.records = 2;
  s.samples = 1000;
  const auto d1 = simulate(bistable(), s);
  s.seed = 2;
  const auto d2 = simulate(bistable(), s);
  REQUIRE(vehs::tools::data_fingerprint(d1) != vehs::tools::data_fingerprint(d2));
  CHECK(vehs::tools::data_fingerprint(d1) == vehs::tools::data_fingerprint(d1));

  auto m1 = bistable();
  auto m2 = bistable();
  m2.drift.push_back({vehs::Term::sign_y(), -0.05});
  vehs::canonicalize(m2.drift, "m2");
  CHECK(vehs::tools::model_hash(m1) != vehs::tools::model_hash(m2));

  vehs::diagnose::Result r;
  r.verdict = vehs::diagnose::Verdict::Inadequate;
  r.score = 12.5;
  vehs::diagnose::Component c;
  c.name = "one_step";
  c.test.available = true;
  c.test.excess = 12.5;
  r.components.push_back(c);

  CHECK(vehs::tools::read_history(path).empty());
  auto e = vehs::tools::append_history(path, vehs::tools::history_entry(m1, "m1.json", "baseline", d1, r));
  REQUIRE(e.size() == 1);
  CHECK(e[0]["version"] == 1);
  r.verdict = vehs::diagnose::Verdict::Adequate;
  r.score = 0.1;
  r.components[0].test.excess = 0.1;
  e = vehs::tools::append_history(path, vehs::tools::history_entry(m2, "m2.json", "with friction", d1, r));
  e = vehs::tools::append_history(path, vehs::tools::history_entry(m2, "m2.json", "other data", d2, r));
  const auto back = vehs::tools::read_history(path);
  REQUIRE(back.size() == 3);
  CHECK(back[1]["version"] == 2);  // second model on the same data
  CHECK(back[2]["version"] == 1);  // first model on other data
  CHECK(back[0]["score"].get<double>() == 12.5);
  CHECK(back[1]["components"]["one_step"].get<double>() == 0.1);
  CHECK(back[1]["verdict"] == "adequate");
  CHECK(back[1]["model_hash"] == vehs::tools::model_hash(m2));
  CHECK(back[1]["model_file"] == "m2.json");
  CHECK(back[1]["time"].get<std::string>().size() == 20);  // 2026-01-01T00:00:00Z
  // the stored model reads back as the model that was diagnosed
  const auto stored = vehs::model_from_json(nlohmann::json::parse(back[1]["model"].dump()), "history");
  CHECK(vehs::tools::model_hash(stored) == vehs::tools::model_hash(m2));

  {
    std::ofstream out(path);
    out << R"({"entries": [{"label": "no score"}]})";
  }
  try {
    vehs::tools::read_history(path);
    FAIL("a history without scores was accepted");
  } catch (const vehs::Error& err) {
    CHECK_THAT(err.what(), Catch::Contains(path) && Catch::Contains("score"));
  }
}
