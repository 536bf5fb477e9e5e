// What a user meets when taking the tools to a rig's files (issue 35, "friction in use"): globs in
// `data`, the columns written once in a measurement file, the estimator's choices in its error, and
// an output named like the config.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tool_runs.hpp"

namespace fs = std::filesystem;
using vehs_tool_test::run_identify;

namespace {

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

/// A logger-style CSV (named columns) of a damped linear oscillator driven by white noise, one
/// record of `n` samples at dt 0.01 (Euler–Maruyama with 10 substeps; a fixed LCG's normals).
void write_run(const fs::path& p, int n, std::uint64_t seed) {
  std::ostringstream s;
  s << "time_s,disp\n";
  double x = 0.0, y = 0.0;
  std::uint64_t state = seed * 2654435761u + 7;
  auto uniform = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double(state >> 11) + 0.5) / double(1ULL << 53);
  };
  const double h = 0.001;
  for (int i = 0; i < n; ++i) {
    s << 0.01 * i << "," << x << "\n";
    for (int k = 0; k < 10; ++k) {
      const double g = std::sqrt(-2.0 * std::log(uniform())) * std::cos(6.283185307179586 * uniform());
      const double a = -x - 0.3 * y;
      x += h * y;
      y += h * a + std::sqrt(0.1 * h) * g;
    }
  }
  write_text(p, s.str());
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

std::string q(const fs::path& p) { return "\"" + p.string() + "\""; }

}  // namespace

TEST_CASE("identify-vehs reads a glob in data in byte order and names a pattern that matches nothing",
          "[identify][app]") {
  const fs::path dir = vehs_tool_test::work_dir("test_friction_globs");
  fs::create_directories(dir / "rig");
  for (const char* name : {"run_b.csv", "run_a.csv", "run_10.csv"}) write_run(dir / "rig" / name, 3000, name[4]);
  const fs::path cfg = dir / "identify.json", out = dir / "model.json";
  fs::remove(out);
  write_text(cfg, "{\"data\": " + q(dir / "rig" / "run_*.csv") + ", \"columns\": {\"t\": \"time_s\", \"x\": \"disp\"}, " +
                      "\"output\": " + q(out) + "}");
  std::string err;
  REQUIRE(run_identify({cfg.string(), "--quiet"}, &err) == 0);
  const nlohmann::json m = read_json(out);
  const std::vector<std::string> files = m["data"]["files"].get<std::vector<std::string>>();
  CHECK(files == std::vector<std::string>{(dir / "rig" / "run_10.csv").string(), (dir / "rig" / "run_a.csv").string(),
                                          (dir / "rig" / "run_b.csv").string()});
  CHECK(m["data"]["records"] == 3);

  // a pattern matching nothing: one line naming the file, the key and the pattern
  write_text(cfg, "{\"data\": [" + q(dir / "rig" / "run_a.csv") + ", " + q(dir / "rig" / "trial_*.csv") +
                      "], \"columns\": {\"t\": \"time_s\", \"x\": \"disp\"}, \"output\": " + q(out) + "}");
  CHECK(run_identify({cfg.string(), "--quiet"}, &err) == 1);
  INFO(err);
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  CHECK(err.find("identify.json: 'data': \"" + (dir / "rig" / "trial_*.csv").string() + "\" matches no file") !=
        std::string::npos);
}

TEST_CASE("identify-vehs takes the data keys once from a measurement file", "[identify][app]") {
  const fs::path dir = vehs_tool_test::work_dir("test_friction_measurement");
  write_run(dir / "run_1.csv", 3000, 3);
  const fs::path rig = dir / "rig.json", cfg = dir / "identify.json", out = dir / "model.json";
  write_text(rig, "{\"data\": " + q(dir / "run_*.csv") +
                      ", \"columns\": {\"t\": \"time_s\", \"x\": \"disp\"}, \"units\": {\"length\": \"mm\", \"time\": \"s\"}}");
  write_text(cfg, "{\"measurement\": " + q(rig) + ", \"output\": " + q(out) + "}");
  fs::remove(out);
  std::string err;
  REQUIRE(run_identify({cfg.string(), "--quiet"}, &err) == 0);
  const nlohmann::json m = read_json(out);
  CHECK(m["data"]["records"] == 1);
  CHECK(m["units"]["length"] == "mm");

  // the config's own key wins: columns that do not exist in the file fail naming them
  write_text(cfg, "{\"measurement\": " + q(rig) + ", \"columns\": {\"t\": \"time_s\", \"x\": \"position\"}, \"output\": " +
                      q(out) + "}");
  CHECK(run_identify({cfg.string(), "--quiet"}, &err) == 1);
  CHECK(err.find("position") != std::string::npos);
  // a key a measurement file cannot hold: one line naming the measurement file
  write_text(rig, "{\"data\": " + q(dir / "run_1.csv") + ", \"colums\": {\"x\": \"disp\"}}");
  write_text(cfg, "{\"measurement\": " + q(rig) + ", \"output\": " + q(out) + "}");
  CHECK(run_identify({cfg.string(), "--quiet"}, &err) == 1);
  INFO(err);
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  CHECK(err.find(rig.string() + ": unknown key 'colums'") != std::string::npos);
  CHECK(err.find("did you mean 'columns'") != std::string::npos);
}

TEST_CASE("identify-vehs lists likelihood among the estimators it refuses", "[identify][app]") {
  const fs::path dir = vehs_tool_test::work_dir("test_friction_estimator");
  write_run(dir / "run.csv", 500, 5);
  const fs::path cfg = dir / "identify.json";
  write_text(cfg, "{\"data\": " + q(dir / "run.csv") + ", \"columns\": {\"t\": \"time_s\", \"x\": \"disp\"}, " +
                      "\"output\": " + q(dir / "m.json") + ", \"estimator\": \"maximum_likelihood\"}");
  std::string err;
  CHECK(run_identify({cfg.string(), "--quiet"}, &err) == 1);
  INFO(err);
  CHECK(err.find("'estimator' must be one of auto, paper, forward, uli, noisy, likelihood (got 'maximum_likelihood')") !=
        std::string::npos);
}

TEST_CASE("identify-vehs refuses an output that is its own config by naming the key and allows a shared name",
          "[identify][app]") {
  const fs::path dir = vehs_tool_test::work_dir("test_friction_output");
  fs::create_directories(dir / "out");
  write_run(dir / "run.csv", 3000, 9);
  const fs::path cfg = dir / "model.json";  // a config named like the model file it writes
  const std::string keys = "{\"data\": " + q(dir / "run.csv") + ", \"columns\": {\"t\": \"time_s\", \"x\": \"disp\"}, ";
  write_text(cfg, keys + "\"output\": " + q(cfg) + "}");
  std::string err;
  CHECK(run_identify({cfg.string(), "--quiet"}, &err) == 1);
  INFO(err);
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  CHECK(err.find("'output' names this config file itself") != std::string::npos);
  CHECK(err.find("change 'output' to another file (e.g. \"" + (dir / "model_out.json").string() + "\")") !=
        std::string::npos);
  CHECK(read_json(cfg)["output"] == cfg.string());  // the config untouched
  // the same name in another folder is another file
  write_text(cfg, keys + "\"output\": " + q(dir / "out" / "model.json") + "}");
  CHECK(run_identify({cfg.string(), "--quiet"}, &err) == 0);
  CHECK(fs::exists(dir / "out" / "model.json"));
}
