// fpk-stationary's density files and statistics JSON (src/tools/fpk_output.cpp).
#include <catch2/catch.hpp>

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "../fpk/fpk_fixtures.hpp"
#include "tools/fpk_output.hpp"
#include "vehs/fpk/stationary.hpp"

using namespace vehs::fpk;
using namespace vehs::tools;

TEST_CASE("density files: CSV and .npy are written atomically with the grid layout", "[tools][fpk]") {
  const FpkModel m(fpk_fixtures::model(R"({"drift": {"x": -1, "y": -0.5}, "diffusion": {"1": 0.2}})"));
  const auto r = solve_stationary(m, automatic_domain(m, 10, 12), SolveOptions{});
  const std::string dir = std::string(VEHS_BINARY_DIR) + "/test_fpk_output";
  write_density(dir + "/p.npy", r);
  write_density(dir + "/p.csv", r);
  std::ifstream npy(dir + "/p.npy", std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(npy)), std::istreambuf_iterator<char>());
  CHECK(all.size() % 64 == (10 * 12 * 8) % 64);
  CHECK(all.find("'shape': (10, 12)") != std::string::npos);
  double last;
  std::memcpy(&last, all.data() + all.size() - 8, 8);
  CHECK(last == r.density.back());
  std::ifstream csv(dir + "/p.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  CHECK(lines == 1 + 10 * 12);
  const auto j = result_to_json(r);
  CHECK(j.contains("E[X^2]"));
  CHECK(j.contains("E[Y^2]"));
  CHECK(j.contains("E[XY]"));
  CHECK(j.contains("boundary_mass"));
  CHECK(j["grid"]["x"][2] == 10);
}
