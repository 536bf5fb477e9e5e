// identify-vehs end to end: measurement files written with vehs::write_measurements, a JSON
// config, the command line run in-process (vehs::tools::identify_main), the model file read back;
// bad inputs give one-line errors and a non-zero exit; and the built executable itself.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "../identify/identify_fixtures.hpp"
#include "tools/tools.hpp"
#include "tools/identify_tool.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"

namespace fs = std::filesystem;
using namespace vehs;

namespace {

fs::path work_dir() {
  const fs::path p = fs::path(VEHS_BINARY_DIR) / "test_identify_work";
  fs::create_directories(p);
  return p;
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

/// Runs identify-vehs in-process; returns the exit code and what it wrote on stderr.
int run(const std::vector<std::string>& args, std::string* err = nullptr) {
  std::vector<std::string> a{"identify-vehs"};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  std::ostringstream captured;
  auto* old = std::cerr.rdbuf(captured.rdbuf());
  const int code = tools::identify_main(static_cast<int>(argv.size()), argv.data());
  std::cerr.rdbuf(old);
  if (err) *err = captured.str();
  return code;
}

}  // namespace

TEST_CASE("identify-vehs: CSV and .npy records to a model file with standard errors", "[identify][app]") {
  const fs::path dir = work_dir();
  const Dataset d = vehs_test::simulate(vehs_test::paper_truth(), 0.001, 1, 10, 100000, 123);
  for (const char* ext : {".csv", ".npy"}) {
    CAPTURE(ext);
    const fs::path data = dir / (std::string("paper") + ext);
    write_measurements(data.string(), d, WriteColumns{false, false, 17});
    const fs::path cfg = dir / "identify.json", out = dir / (std::string("model") + ext + ".json");
    write_text(cfg, "{\"data\": [\"" + data.string() + "\"], \"output\": \"" + out.string() + "\"}");
    fs::remove(out);
    std::string err;
    REQUIRE(run({cfg.string(), "--quiet"}, &err) == 0);
    const ModelFile file = read_model_file(out.string());
    const Model& m = file.model;
    // the same data twice (CSV, .npy): one draw, so the family is the 8 z-checks and one support
    vehs_test::check_support(m, vehs_test::paper_truth(), 11);
    for (const auto& tc : m.drift) CHECK(m.drift_stderr.count(tc.term.name()) == 1);
    for (const auto& tc : m.diffusion) CHECK(m.diffusion_stderr.count(tc.term.name()) == 1);
    for (const char* key : {"estimator", "sampling", "residuals", "selection", "fit", "data", "provenance"})
      CHECK(file.sections.contains(key));
    CHECK(file.sections["data"]["records"] == 10);
    // the paper's sampling (ω̂Δt ≈ 0.04): the expansions are vouched for and the file says so
    const auto& adequacy = file.sections["estimator"]["sampling_adequacy"];
    CHECK(adequacy["vouched"] == true);
    CHECK(adequacy["likelihood"] == "not used");
    CHECK(adequacy["omega_dt"].get<double>() < 0.1);
    CHECK(adequacy["reason"].get<std::string>().find("the expansions in dt hold") != std::string::npos);
    CHECK(vehs_test::compare(m, vehs_test::paper_truth()).max_z <= vehs_test::z_limit(8));
  }
}

TEST_CASE("identify-vehs: bad configs and bad files fail with one line naming the problem", "[identify][app]") {
  const fs::path dir = work_dir();
  std::string err;
  const fs::path cfg = dir / "bad.json";
  write_text(cfg, R"({"data": ["x.csv"], "output": "m.json", "drift_libary": {"K1": 3}})");
  CHECK(run({cfg.string()}, &err) == 1);
  CHECK(err.find("unknown key 'drift_libary'") != std::string::npos);
  CHECK(err.find("did you mean 'drift_library'") != std::string::npos);

  // non-uniform sampling in a file
  const fs::path csv = dir / "jitter.csv";
  std::ostringstream text;
  text << "t,x\n";
  for (int i = 0; i < 100; ++i) text << (i < 50 ? 0.01 * i : 0.01 * i + 0.003) << "," << std::sin(0.1 * i) << "\n";
  write_text(csv, text.str());
  write_text(cfg, "{\"data\": [\"" + csv.string() + "\"], \"output\": \"" + (dir / "m.json").string() + "\"}");
  CHECK(run({cfg.string(), "--quiet"}, &err) == 1);
  CHECK(err.find("jitter.csv: line 52") != std::string::npos);
  CHECK(err.find("non-uniform sampling") != std::string::npos);
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "m.json"));

  // a NaN in a file
  write_text(csv, "t,x\n0,1\n0.01,2\n0.02,nan\n");
  CHECK(run({cfg.string(), "--quiet"}, &err) == 1);
  CHECK(err.find("line 4") != std::string::npos);

  // a library term that does not exist, an unknown estimator, a dynamic effect
  for (const char* extra : {R"("drift_library": ["x", "x^^2"])", R"("estimator": "magic")",
                                   R"("effects": ["colored_noise", "harmonic_forcing"])", R"("study": {"truth": {}})"}) {
    write_text(cfg, "{\"data\": [\"" + csv.string() + "\"], \"output\": \"m.json\", " + std::string(extra) + "}");
    CHECK(run({cfg.string(), "--quiet"}, &err) == 1);
    INFO(err);
    CHECK(std::count(err.begin(), err.end(), '\n') == 1);
    CHECK(err.find("bad.json") != std::string::npos);
  }
}

TEST_CASE("identify-vehs: the consistency study writes the paper's Table 4 layout", "[identify][app][study]") {
  const fs::path dir = work_dir();
  const fs::path cfg = dir / "study.json", out = dir / "study_out.json";
  write_text(cfg, "{\"output\": \"" + out.string() + R"(",
    "study": {"truth": {"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
                        "diffusion": {"1": 0.02, "x^2": 0.01}},
              "dt": [0.005, 0.01], "samples": 20000, "repeats": 3, "records": 4, "substeps": 10}})");
  std::string err;
  REQUIRE(run({cfg.string(), "--quiet"}, &err) == 0);
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  REQUIRE(j["points"].size() == 2);
  CHECK(j["points"][0]["parameters"].contains("beta"));
  CHECK(j["points"][1]["parameters"]["2D"]["truth"] == 0.02);
  CHECK(j["intervals"] == 2 * 3 * 8);
  CHECK(fs::exists(dir / "study_out.csv"));
}

TEST_CASE("the identify-vehs executable runs (--help lists every key)", "[identify][app]") {
  const fs::path exe = fs::path(VEHS_BINARY_DIR) / "identify-vehs";
  REQUIRE(fs::exists(exe));
  const fs::path help = work_dir() / "help.txt";
  REQUIRE(std::system((exe.string() + " --help > " + help.string()).c_str()) == 0);
  std::ifstream in(help);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& k : tools::identify_schema().keys) CHECK(text.find(k.name) != std::string::npos);
}

TEST_CASE("identify-vehs: a user's own effect in the config - its parameters, or one line naming the key",
          "[identify][app][user]") {
  const fs::path dir = work_dir();
  const Dataset d = vehs_test::simulate(vehs_test::paper_truth(), 0.001, 1, 4, 50000, 7);
  const fs::path data = dir / "user_effect.csv", out = dir / "user_effect_model.json", cfg = dir / "user_effect.json";
  write_measurements(data.string(), d, WriteColumns{false, false, 17});
  auto config = [&](const std::string& effect) {
    write_text(cfg, "{\"data\": [\"" + data.string() + "\"], \"output\": \"" + out.string() +
                        "\", \"drift_library\": [\"x\", \"x^5\", \"x^7\", \"x^9\", \"y\"], \"diffusion_library\": [\"1\", \"x^2\"], "
                        "\"sparsity\": \"none\", "
                        "\"effects\": [" + effect + "]}");
  };
  // the paper's cubic stiffness written as the user's own effect (the other terms of the paper's
  // polynomial in the library): k3 = −coef of x^3
  config(R"J({"name": "cubic_spring", "drift": {"k3": "-x^3"}})J");
  fs::remove(out);
  std::string err;
  REQUIRE(run({cfg.string(), "--quiet"}, &err) == 0);
  const ModelFile file = read_model_file(out.string());
  const auto& params = file.sections["effect_params"];
  REQUIRE(params.size() == 1);
  CHECK(params[0]["name"] == "cubic_spring");
  CHECK(params[0]["user"] == true);
  const double k3 = params[0]["params"]["k3"].get<double>(), se = params[0]["stderr"]["k3"].get<double>();
  const double truth = -vehs_test::paper_truth().drift_coef("x^3");
  INFO("k3 " << k3 << " +- " << se << ", truth " << truth);
  CHECK(std::abs(k3 - truth) < 4.5 * se);  // false failure 6.8e-6 for a consistent fit
  CHECK(file.model.drift_coef("-x^3") == Approx(k3));

  for (const auto& [effect, expected] : std::vector<std::pair<std::string, std::string>>{
           {R"J({"name": "f", "drift": {"a": "x^^2"}})J", "[0].drift.a: unknown term 'x^^2'"},
           {R"J({"name": "f", "drift": {"a": 3}})J", "[0].drift.a must be a term"},
           {R"J({"name": "f", "drift": {"a": "x^2"}, "extra": 1})J", "unknown key 'extra'"},
           {R"J({"name": "coulomb_friction", "drift": {"a": "x^2"}})J", "is a catalogue effect"},
           {R"J({"name": "f", "drift": {"a": "x^2", "b": "x^2"}})J", "belongs to two parameters"},
           {R"J({"name": "f", "diffusion": {"a": "sign(y)"}})J", "not allowed in the diffusion"}}) {
    config(effect);
    CHECK(run({cfg.string(), "--quiet"}, &err) == 1);
    INFO(effect << " -> " << err);
    CHECK(err.find(expected) != std::string::npos);
    CHECK(err.find("user_effect.json") != std::string::npos);
    CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  }
}
