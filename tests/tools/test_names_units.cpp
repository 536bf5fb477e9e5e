// Effect parameters by their physical names and every parameter with its unit, from the CLI:
// identify-vehs's and diagnose-vehs's parameter tables, fpk-stationary's sweeps.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../identify/identify_fixtures.hpp"
#include "tools/parameter_table.hpp"
#include "vehs/io/parameter_units.hpp"
#include "tool_runs.hpp"
#include "vehs/io/model_file.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kBinary = VEHS_BINARY_DIR;

using vehs_tool_test::slurp;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The line of `text` that starts (after spaces) with `name` followed by a space.
std::string line_of(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto start = line.find_first_not_of(' ');
    if (start != std::string::npos && line.compare(start, name.size() + 1, name + " ") == 0) return line;
  }
  return "";
}

}  // namespace

TEST_CASE("parameter units are derived from the term's powers and the data's units", "[tools][units]") {
  const nlohmann::json mm_s = {{"length", "mm"}, {"time", "s"}, {"input", "V"}};
  using vehs::parameter_unit;
  CHECK(parameter_unit("beta", mm_s) == "1/s");
  CHECK(parameter_unit("k1", mm_s) == "1/s^2");
  CHECK(parameter_unit("k3", mm_s) == "1/(mm^2 s^2)");
  CHECK(parameter_unit("coulomb_friction.mu", mm_s) == "mm/s^2");
  CHECK(parameter_unit("quadratic_damping.c", mm_s) == "1/mm");
  CHECK(parameter_unit("2D", mm_s) == "mm^2/s^3");
  CHECK(parameter_unit("drift[u]", mm_s) == "mm/(V s^2)");
  CHECK(parameter_unit("harmonic_forcing.phase", mm_s) == "rad");
  CHECK(parameter_unit("beta", nlohmann::json::object()) == "1/time");
  // a compound input unit (a base acceleration) stays one unit inside the product
  const nlohmann::json accel = {{"length", "mm"}, {"time", "s"}, {"input", "m/s^2"}};
  CHECK(parameter_unit("drift[u]", accel) == "(mm/s^2)/(m/s^2)");
  CHECK(vehs::unit_text({0, -2, -1}, accel) == "(1/s^2)/(m/s^2)");
  CHECK(vehs::unit_text({0, 0, 1}, accel) == "m/s^2");
  CHECK(vehs::unit_text({0, 0, -1}, accel) == "1/(m/s^2)");
}

TEST_CASE("identify-vehs prints friction as coulomb_friction.mu with units and fpk-stationary sweeps mu",
          "[tools][units][names]") {
  const fs::path dir = fresh_dir("vehs_names_units");
  // a bistable harvester with dry friction, recorded in mm (1 unit = 2 mm) and s (1 unit = 20 ms)
  const double L_mm = 2.0, T_s = 0.02, dt = 0.01, mu = 0.1;
  const vehs::Model truth = vehs::model_from_json(nlohmann::json::parse(R"J({
    "drift": {"x": 1.0, "x^3": -1.0, "y": -0.1, "sign(y)": -0.1}, "diffusion": {"1": 0.1}})J"), "truth");
  const vehs::Dataset d = vehs_test::simulate(truth, dt, 20, 1, 100000, 35);
  {
    std::ofstream csv(dir / "rig.csv");
    csv << "t,x\n";
    csv.precision(10);
    for (std::size_t i = 0; i < d.x.size(); ++i) csv << i * dt * T_s << "," << d.x[i] * L_mm << "\n";
  }
  std::ofstream(dir / "identify.json")
      << R"({"data": ")" << (dir / "rig.csv").string() << R"(", "output": ")" << (dir / "model.json").string()
      << R"(", "units": {"length": "mm", "time": "s"}, "effects": ["coulomb_friction"], )"
      << R"("drift_library": ["x", "x^3", "y"], "diffusion_library": ["1"], "sparsity": "none", "likelihood": {"use": "never"}})";
  REQUIRE(std::system(((kBinary / "identify-vehs").string() + " " + (dir / "identify.json").string() + " > " +
                       (dir / "stdout.txt").string() + " 2> " + (dir / "stderr.txt").string())
                          .c_str()) == 0);
  const std::string out = slurp(dir / "stdout.txt");
  INFO(out);
  const std::string friction = line_of(out, "coulomb_friction.mu");
  CHECK(friction.find("mm/s^2") != std::string::npos);
  CHECK(friction.find("-drift[sign(y)]") != std::string::npos);
  CHECK(line_of(out, "beta").find("1/s") != std::string::npos);
  CHECK(line_of(out, "2D").find("mm^2/s^3") != std::string::npos);
  CHECK(line_of(out, "drift[sign(y)]").empty());  // not as a raw coefficient
  // mu in mm/s^2 = mu · L/T², within 6 standard errors (a false failure < 1e-8)
  const vehs::ModelFile f = vehs::read_model_file((dir / "model.json").string());
  const double mu_mm = mu * L_mm / (T_s * T_s);
  CHECK(std::abs(vehs::get_parameter(f.model, "mu") - mu_mm) < 6.0 * f.model.drift_stderr.at("sign(y)"));

  // the sweep over the friction level, by its short and its full name
  for (const std::string name : {"mu", "coulomb_friction.mu"}) {
    CAPTURE(name);
    std::ofstream(dir / "fpk.json") << R"({"model": ")" << (dir / "model.json").string() << R"(", "output": ")"
                                    << (dir / "fpk_out.json").string() << R"(", "grid": {"x": 40, "y": 40}, )"
                                    << R"("sweep": {")" << name << R"(": [)" << 0.5 * mu_mm << ", " << 2 * mu_mm << R"(, 3]}})";
    REQUIRE(std::system(((kBinary / "fpk-stationary").string() + " -q " + (dir / "fpk.json").string() + " 2> " +
                         (dir / "fpk_err.txt").string())
                            .c_str()) == 0);
    const std::string table = slurp(dir / "fpk_out.sweep.csv");
    CHECK(table.rfind(name + ",", 0) == 0);
    CHECK(std::count(table.begin(), table.end(), '\n') == 4);
  }
}
