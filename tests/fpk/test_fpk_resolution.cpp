// A grid too coarse for the model: solve_with_domain refines it (and says so) or names the cells
// needed — never "heavy tails?" for what is a resolution problem (the paper's penta-stable model
// failed at 100², 160² and 200² that way).
#include <catch2/catch.hpp>

#include "vehs/core/error.hpp"
#include "vehs/fpk/stationary.hpp"
#include "vehs/io/model_file.hpp"

namespace {
vehs::Model paper() {
  return vehs::model_from_json(nlohmann::json::parse(R"({
    "drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
    "diffusion": {"1": 0.02, "x^2": 0.01}})"), "paper");
}
}  // namespace

TEST_CASE("an under-resolved automatic grid is refined, or the error names the cells needed", "[fpk][resolution]") {
  const vehs::fpk::FpkModel fm(paper(), "paper");
  vehs::fpk::GridRequest coarse;
  coarse.grid.x.n = coarse.grid.y.n = 100;
  const auto r = vehs::fpk::solve_with_domain(fm, coarse, vehs::fpk::SolveOptions{});
  CHECK(r.refinements >= 1);
  CHECK(r.grid.x.n == 100 << r.refinements);
  vehs::fpk::GridRequest fine;
  fine.grid.x.n = fine.grid.y.n = r.grid.x.n;
  const auto f = vehs::fpk::solve_with_domain(fm, fine, vehs::fpk::SolveOptions{});
  CHECK(f.refinements == 0);
  CHECK(r.moments.exx == Approx(f.moments.exx).epsilon(1e-12));  // the same grid, the same solve
  vehs::fpk::DomainOptions no_refinement;
  no_refinement.max_cells = 0;
  try {
    vehs::fpk::solve_with_domain(fm, coarse, vehs::fpk::SolveOptions{}, no_refinement);
    FAIL("no error on an under-resolved grid");
  } catch (const vehs::Error& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Catch::Contains("does not resolve the model") && Catch::Contains("at least 200x200 cells"));
    CHECK_THAT(what, !Catch::Contains("heavy tails"));
  }
}

TEST_CASE("a grid of 5x5 cells, where the solve has no positive mass, is refined like any "
          "under-resolved grid", "[fpk][resolution]") {
  // a new user's {"grid": {"x": 5, "y": 5}} stopped with "the solve broke down" (25 Nov 2026)
  const vehs::fpk::FpkModel fm(vehs::model_from_json(nlohmann::json::parse(R"({
    "drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.02}})"), "bistable"), "bistable");
  vehs::fpk::GridRequest tiny;
  tiny.grid.x.n = tiny.grid.y.n = 5;
  const auto r = vehs::fpk::solve_with_domain(fm, tiny, vehs::fpk::SolveOptions{});
  CHECK(r.refinements >= 1);
  CHECK(r.grid.x.n == 5 << r.refinements);
  vehs::fpk::DomainOptions no_refinement;
  no_refinement.max_cells = 0;
  CHECK_THROWS_WITH(vehs::fpk::solve_with_domain(fm, tiny, vehs::fpk::SolveOptions{}, no_refinement),
                    Catch::Contains("does not resolve the model") && Catch::Contains("at least 10x10 cells"));
}
