// A user's own data through the executables: a logger CSV in physical units (mm, s, `;`, BOM,
// comments, 6-decimal stamps, a gap and a NaN run) to a model file with units, covariance and
// finite standard errors; --version on every tool; progress in a log without carriage returns.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../identify/identify_fixtures.hpp"
#include "io/logger_files.hpp"
#include "tool_runs.hpp"
#include "vehs/io/model_file.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kBinary = VEHS_BINARY_DIR;

using vehs_tool_test::slurp;

}  // namespace

TEST_CASE("every tool prints its version", "[tools][version]") {
  const fs::path out = fs::temp_directory_path() / "vehs_version.txt";
  for (const char* tool : {"simulate-vehs", "identify-vehs", "fpk-stationary", "diagnose-vehs", "vehs-compare"}) {
    CAPTURE(tool);
    REQUIRE(std::system(((kBinary / tool).string() + " --version > " + out.string()).c_str()) == 0);
    CHECK(slurp(out).find(std::string(tool) + " (vehs 0.1.0)") != std::string::npos);
  }
}

TEST_CASE("identify-vehs on a logger CSV in mm and s: units, covariance, finite errors, split records",
          "[tools][units][logger]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_user_data";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // the paper's harvester in physical units: 1 unit of x = 2 mm, 1 unit of time = 20 ms
  const double L_mm = 2.0, T_s = 0.02, dt = 0.005;
  const vehs::Dataset d = vehs_test::simulate(vehs_test::paper_truth(), dt, 1, 1, 200000, 5);
  std::vector<double> x(d.x.begin(), d.x.end());
  vehs::test::LoggerStyle s;
  s.t_name = "time_s";
  s.x_name = "disp_mm";
  s.length_factor = L_mm;
  s.gap_at = 50000, s.gap_rows = 300;
  s.nan_at = 120000, s.nan_rows = 4;
  vehs::test::write_logger_csv((dir / "logger.csv").string(), x, {}, dt * T_s, s);
  std::ofstream(dir / "identify.json")
      << R"({"data": [")" << (dir / "logger.csv").string() << R"("], "output": ")" << (dir / "model.json").string()
      << R"(", "columns": {"t": "time_s", "x": "disp_mm"}, "units": {"length": "mm", "time": "s"}, )"
      // the true terms (one record of 1000 time units does not separate y from x^2*y reliably;
      // this test is about units and reading, not selection)
      << R"("drift_library": ["x", "x^3", "x^5", "x^7", "x^9", "y"], "diffusion_library": ["1", "x^2"], )"
      << R"("figures": ")" << (dir / "figures").string() << R"("})";
  const std::string cmd = (kBinary / "identify-vehs").string() + " " + (dir / "identify.json").string() + " > " +
                          (dir / "stdout.txt").string() + " 2> " + (dir / "stderr.txt").string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  const std::string err = slurp(dir / "stderr.txt");
  CHECK(err.find('\r') == std::string::npos);  // stderr is a file: progress as lines, if any
  CHECK(err.find("1 time gap(s) and 1 run(s) of missing values") != std::string::npos);
  const vehs::ModelFile f = vehs::read_model_file((dir / "model.json").string());
  CHECK(f.sections["units"]["length"] == "mm");
  // the figure of the fit: axes in the data's units, the model's band and the binned estimates
  const std::string svg = slurp(dir / "figures" / "identify_fit.svg");
  CHECK(svg.find("x [mm]") != std::string::npos);
  CHECK(svg.find("a22 [mm^2/s^3]") != std::string::npos);
  CHECK(svg.find("model, 95 % band") != std::string::npos);
  CHECK(fs::file_size(dir / "figures" / "identify_fit_km_x.csv") > 200);
  CHECK(f.sections["data"]["reading"]["gaps_split"] == 1);
  CHECK(f.sections["data"]["reading"]["missing_runs_split"] == 1);
  CHECK(f.sections["data"]["records"] == 3);
  const vehs::Model& m = f.model;
  REQUIRE_FALSE(m.covariance.empty());
  for (const auto& [n, se] : m.drift_stderr) CHECK(std::isfinite(se));
  for (const auto& [n, se] : m.diffusion_stderr) CHECK(std::isfinite(se));
  // the truth in mm and s: drift[x^p] scales by (L/T^2)/L^p, diffusion[1] by L^2/T^3, drift[y] by 1/T.
  // z-checks of 4 coefficients at |z| < 5.5 (identify's z spread over seeds is ≈ 1.15 of N(0,1):
  // |z| > 4.8 has probability 1.6e-6 each; 4 checks: < 1e-5 per run)
  const vehs::Model truth = vehs_test::paper_truth();
  auto z = [&](const char* term, double scale, bool diffusion) {
    const double learned = diffusion ? m.diffusion_coef(term) : m.drift_coef(term);
    const double se = (diffusion ? m.diffusion_stderr : m.drift_stderr).at(term);
    const double t = (diffusion ? truth.diffusion_coef(term) : truth.drift_coef(term)) * scale;
    return (learned - t) / se;
  };
  const double acc = L_mm / (T_s * T_s);
  CHECK(std::abs(z("x", acc / L_mm, false)) < 5.5);
  CHECK(std::abs(z("x^3", acc / std::pow(L_mm, 3), false)) < 5.5);
  CHECK(std::abs(z("y", 1.0 / T_s, false)) < 5.5);
  CHECK(std::abs(z("1", L_mm * L_mm / std::pow(T_s, 3), true)) < 5.5);
}

TEST_CASE("identify-vehs on the Silverbox data (volts) writes a model the other tools accept", "[tools][units][silverbox][long]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_user_data_silverbox";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string cmd = "cd " + std::string(VEHS_SOURCE_DIR) + " && " + (kBinary / "identify-vehs").string() +
                          " data/identify/silverbox.json -q --set 'output=\"" + (dir / "model.json").string() +
                          "\"' --set 'units={\"length\": \"V\", \"time\": \"s\", \"input\": \"V\"}'";
  REQUIRE(std::system(cmd.c_str()) == 0);
  // what fpk-stationary and diagnose-vehs do first: read and check the model file (every
  // standard error a finite number, the covariance valid)
  const vehs::ModelFile f = vehs::read_model_file((dir / "model.json").string());
  vehs::validate_model(f.model, "silverbox");
  CHECK(f.model.diffusion_stderr.count("x^2") == (f.model.diffusion_coef("x^2") != 0.0 ? 1u : 0u));
  for (const auto& [n, se] : f.model.diffusion_stderr) CHECK(std::isfinite(se));
  CHECK_FALSE(f.model.covariance.empty());
  CHECK(f.sections["units"]["length"] == "V");
}
