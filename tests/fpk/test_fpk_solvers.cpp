// Solvers, domains, wells, sweeps and the errors of models without a stationary density.
// Deterministic (no random numbers): tolerances are discretisation and solver bounds.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "fpk_fixtures.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/fpk/stationary.hpp"

using namespace vehs::fpk;
using Catch::Contains;

namespace {
double l1_between(const StationaryResult& a, const StationaryResult& b) {
  double s = 0.0;
  for (std::size_t k = 0; k < a.density.size(); ++k) s += std::abs(a.density[k] - b.density[k]);
  return s * a.grid.cell_area();
}
}  // namespace

TEST_CASE("models without a stationary 2-D density are rejected with a reason", "[fpk][errors]") {
  auto fm = [](const char* json) { return FpkModel(fpk_fixtures::model(json), "m.json"); };
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "x^2": 1, "y": -0.1}, "diffusion": {"1": 0.02}})"),
                    Contains("does not confine") && Contains("even"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "x^3": 1, "y": -0.1}, "diffusion": {"1": 0.02}})"),
                    Contains("does not confine") && Contains("pushes outwards"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": 1, "y": -0.1}, "diffusion": {"1": 0.02}})"), Contains("does not confine"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1}, "diffusion": {"1": 0.02}})"), Contains("damping"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {}})"), Contains("diffusion is zero"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": -0.02}})"), Contains("negative"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "y": -0.1, "u": 1}, "diffusion": {"1": 0.02}})"),
                    Contains("'u'") && Contains("time-dependent"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": 0.02},
                           "effects": [{"name": "harmonic_forcing", "params": {"amplitude": 0.1, "omega": 1}}]})"),
                    Contains("harmonic_forcing") && Contains("time-dependent"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": 0.02},
                           "effects": [{"name": "colored_noise", "params": {"tau": 0.1, "intensity": 0.02}}]})"),
                    Contains("colored_noise") && Contains("not Markov"));
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": 0.02},
                           "effects": [{"name": "electromechanical_coupling", "params": {"lambda": 1, "coupling": 0.1}}]})"),
                    Contains("electromechanical_coupling") && Contains("not Markov"));
  // NaN coefficient (set programmatically; JSON cannot hold NaN)
  vehs::Model nan_model = fpk_fixtures::model(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": 0.02}})");
  nan_model.drift[0].coef = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(FpkModel(nan_model, "m.json"), Contains("not finite"));
  // diffusion negative for large |x|: refused whatever the grid (simulate-vehs's and
  // diagnose-vehs's rule; fpk-stationary solved it on a grid that did not reach |x| = 1.41)
  CHECK_THROWS_WITH(fm(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": 0.02, "x^2": -0.01}})"),
                    Contains("m.json: diffusion a22(x, 0) = 0.02 - 0.01·x^2 has leading term -0.01·x^2 and turns "
                             "negative at |x| = 1.414"));
  // diffusion that turns negative inside the grid only: named with the point
  const FpkModel neg = fm(R"({"drift": {"x": -1, "y": -0.1}, "diffusion": {"1": 0.02, "x^2": -0.05, "x^4": 0.01}})");
  Grid g;
  g.x = {-2, 2, 20};
  g.y = {-2, 2, 20};
  CHECK_THROWS_WITH(assemble_operator(neg, g, Scheme::Flux), Contains("negative at (x, y)"));
  // negative damping somewhere: no dissipation
  const FpkModel anti = fm(R"({"drift": {"x": -1, "y": -0.1, "x^2*y": 0.5}, "diffusion": {"1": 0.02}})");
  CHECK_THROWS_WITH(automatic_domain(anti, 50, 50), Contains("no dissipation"));
  // sign(y) cannot be expanded by the central scheme
  const FpkModel friction = fm(R"J({"drift": {"x": -1, "y": -0.1, "sign(y)": -0.05}, "diffusion": {"1": 0.02}})J");
  CHECK_THROWS_WITH(assemble_operator(friction, g, Scheme::Central), Contains("sign(y)"));
}

TEST_CASE("a user domain holding too much mass at its boundary is an error, an automatic one grows", "[fpk][domain]") {
  const FpkModel m(fpk_fixtures::paper_learned());
  GridRequest paper;  // the paper's domain [−1.6, 1.6]² is too small in y for this model
  paper.auto_x = paper.auto_y = false;
  paper.grid.x = {-1.6, 1.6, 50};
  paper.grid.y = {-1.6, 1.6, 50};
  CHECK_THROWS_WITH(solve_with_domain(m, paper, SolveOptions{}),
                    Contains("grid.y [-1.6, 1.6]") && Contains("boundary cells") &&
                        Contains("boundary_mass_tolerance"));
  // automatic y on a deliberately tight start: K = 3 e-folds → widened until the mass fits
  GridRequest tight;
  tight.grid.x.n = tight.grid.y.n = 200;
  DomainOptions small;
  small.log_density_drop = 3.0;
  const auto r = solve_with_domain(m, tight, SolveOptions{}, small);
  CHECK(r.boundary_mass <= 1e-6);
  CHECK(r.domain_enlargements > 0);
}

TEST_CASE("the automatic velocity range grows with the multiplicative noise", "[fpk][domain]") {
  const Grid g0 = automatic_domain(FpkModel(fpk_fixtures::paper_learned(0.0194, 0.0)), 50, 50);
  const Grid g1 = automatic_domain(FpkModel(fpk_fixtures::paper_learned(0.0194, 0.0116)), 50, 50);
  const Grid g2 = automatic_domain(FpkModel(fpk_fixtures::paper_learned(0.0194, 0.05)), 50, 50);
  CHECK(g1.y.max > 1.2 * g0.y.max);
  CHECK(g2.y.max > 1.2 * g1.y.max);
  CHECK(g2.x.max >= g1.x.max);
}

TEST_CASE("wells of the penta-stable potential: five, symmetric, masses sum to one", "[fpk][wells]") {
  const FpkModel m(fpk_fixtures::paper_learned());
  Grid g = automatic_domain(m, 160, 160);
  const auto r = solve_stationary(m, g, SolveOptions{});
  REQUIRE(r.wells.size() == 5);
  double total = 0.0;
  for (const auto& w : r.wells) total += w.mass;
  CHECK(total == Approx(1.0).epsilon(1e-12));
  CHECK(r.wells[0].mass == Approx(r.wells[4].mass).epsilon(1e-6));
  CHECK(r.wells[1].mass == Approx(r.wells[3].mass).epsilon(1e-6));
  CHECK(r.wells[2].x_min == Approx(0.0).margin(1e-9));
  // the potential's minima: U'(x_min) = 0
  for (const auto& w : r.wells) CHECK(std::abs(m.restoring_force(w.x_min)) < 1e-9);
}

TEST_CASE("wells: a grid point exactly on a root is counted once", "[fpk][wells]") {
  // U' = x − 4x³ + 3x⁵ (tristable: minima at 0 and ±1). On [−2, 2] with 4000 steps the scan
  // lands exactly on x = 0 (−2 + 2000·0.001 rounds to 0); the root was counted twice on
  // machines where it did (6 wells for the penta-stable model in a portable build).
  const FpkModel m(fpk_fixtures::model(
      R"({"drift": {"x": -1, "x^3": 4, "x^5": -3, "y": -0.1}, "diffusion": {"1": 0.02}})"));
  REQUIRE(m.restoring_force(-2.0 + 2000 * ((2.0 - -2.0) / 4000)) == 0.0);
  const auto wells = find_wells(m, -2.0, 2.0);
  REQUIRE(wells.size() == 3);
  CHECK(wells[1].x_min == Approx(0.0).margin(1e-12));
  CHECK(wells[0].x_min == Approx(-1.0).epsilon(1e-9));
  CHECK(wells[2].x_min == Approx(1.0).epsilon(1e-9));
}

TEST_CASE("impact_stop is supported: identities converge with the stop force", "[fpk][effects]") {
  // negative stiffness between soft stops: a double well whose potential has a kink at |x| = 1
  const FpkModel m(fpk_fixtures::model(R"({"drift": {"x": 0.5, "y": -0.3}, "diffusion": {"1": 0.1},
      "effects": [{"name": "impact_stop", "params": {"k_stop": 5, "gap": 1.0}}]})"));
  double energy[2];
  for (int k = 0; k < 2; ++k) {
    const int n = 100 << k;
    const auto r = solve_stationary(m, automatic_domain(m, n, n), SolveOptions{});
    std::printf("impact_stop n=%d: E[XY]/scale %.1e, virial %.1e, energy %.1e, negative mass %.1e\n", n,
                r.identities.xy, r.identities.virial, r.identities.energy, r.summary.negative_mass);
    CHECK(r.wells.size() == 2);
    CHECK(std::abs(r.identities.xy) < 1e-4);
    CHECK(std::abs(r.identities.virial) < 1e-3);
    energy[k] = std::abs(r.identities.energy);
  }
  CHECK(energy[0] / energy[1] >= 3.0);
}

TEST_CASE("the paper's SOR stops early, BiCGSTAB matches the direct solve", "[fpk][solvers]") {
  const FpkModel m(fpk_fixtures::model(R"({"drift": {"x": -1, "x^3": -1, "y": -0.5}, "diffusion": {"1": 0.2, "x^2": 0.05}})"));
  const Grid g = automatic_domain(m, 40, 40);
  SolveOptions exact_lu;  // the exact solution of the discrete system, to compare iterations with
  exact_lu.correction_steps = 0;
  const auto rd = solve_stationary(m, g, exact_lu);
  SolveOptions it;
  it.solver = Solver::Bicgstab;
  const auto rb = solve_stationary(m, g, it);
  CHECK(rb.summary.converged);
  CHECK(l1_between(rb, rd) < 1e-6);
  // The paper's settings (α = 0.01, tolerance 1e-5 on the change per sweep) stop while the
  // density is still far from the discrete solution; a tighter tolerance gets much closer.
  SolveOptions paper;
  paper.solver = Solver::Sor;
  const auto rp = solve_stationary(m, g, paper);
  SolveOptions tight = paper;
  tight.sor.tolerance = 1e-7;
  const auto rt = solve_stationary(m, g, tight);
  std::printf("SOR alpha 0.01 on 40x40: tol 1e-5: %ld sweeps, L1 to direct %.2e; tol 1e-7: %ld sweeps, L1 %.2e\n",
              rp.summary.iterations, l1_between(rp, rd), rt.summary.iterations, l1_between(rt, rd));
  CHECK(rp.summary.converged);
  CHECK(rp.summary.iterations >= 10);
  CHECK(l1_between(rt, rd) < 0.1 * l1_between(rp, rd));
  CHECK(l1_between(rt, rd) < 1e-3);
}

TEST_CASE("the direct solver: a grid over the memory limit is refused before any work, phases logged", "[fpk][solvers]") {
  const FpkModel m(fpk_fixtures::model(R"({"drift": {"x": -1, "x^3": -1, "y": -0.5}, "diffusion": {"1": 0.2}})"));
  const Grid g = automatic_domain(m, 60, 60);
  SolveOptions o;
  o.correction_steps = 0;
  std::vector<std::string> lines;
  o.log = [&](const std::string& line) { lines.push_back(line); };
  o.memory_limit = 0.5 * estimated_solve_bytes(g.size(), o);
  CHECK_THROWS_WITH(solve_stationary(m, g, o), Contains("60x60 cells need about") && Contains("use fewer cells"));
  CHECK(lines.empty());  // refused before the factorisation
  o.memory_limit = 0.0;
  (void)solve_stationary(m, g, o);
  REQUIRE(lines.size() == 3);
  CHECK(lines[0] == "factorising 60x60 cells (symbolic)...");
  CHECK(lines[1] == "factorising 60x60 cells (numeric)...");
  CHECK(lines[2].rfind("factorised in ", 0) == 0);
  CHECK(lines[2].find(" s (symbolic) + ") != std::string::npos);
  // the estimates grow as the measured costs do: memory ~N log N, time ~N^1.5 (nested dissection)
  CHECK(estimated_solve_seconds(4 * g.size(), o) == Approx(8.0 * estimated_solve_seconds(g.size(), o)));
  SolveOptions sor;
  sor.solver = Solver::Sor;
  CHECK(estimated_solve_seconds(g.size(), sor) == 0.0);
}

TEST_CASE("sweeps: one grid, results independent of the thread count and equal to single solves", "[fpk][sweep]") {
  // a bistable Duffing oscillator with multiplicative noise, well resolved on 80x80 cells
  const vehs::Model base =
      fpk_fixtures::model(R"({"drift": {"x": 1, "x^3": -1, "y": -0.3}, "diffusion": {"1": 0.0194, "x^2": 0.0116}})");
  std::vector<SweepAxis> axes = {{"2D", {0.015, 0.0194, 0.025}}, {"2Q", {0.008, 0.0116}}};
  GridRequest req;
  req.grid.x.n = req.grid.y.n = 80;
  vehs::set_threads(1);
  const SweepResult s1 = sweep(base, axes, req);
  vehs::set_threads(2);
  const SweepResult s2 = sweep(base, axes, req);
  vehs::set_threads(0);
  REQUIRE(s1.points.size() == 6);
  for (std::size_t k = 0; k < 6; ++k) {
    INFO("point " << k << ": " << s1.points[k].error);
    CHECK(s1.points[k].error.empty());
    CHECK(s1.points[k].moments.eyy == s2.points[k].moments.eyy);  // bitwise
    CHECK(s1.points[k].moments.exx == s2.points[k].moments.exx);
  }
  // last axis fastest; point 3 = (2D = 0.0194, 2Q = 0.0116) = the base model on the same grid
  CHECK(s1.points[3].parameters[0] == 0.0194);
  CHECK(s1.points[3].parameters[1] == 0.0116);
  const auto single = solve_stationary(FpkModel(base), s1.grid, SolveOptions{});
  CHECK(s1.points[3].moments.eyy == Approx(single.moments.eyy).epsilon(1e-10));
  // more noise → more power (the paper's Fig. 5a trend)
  CHECK(s1.points[5].moments.eyy > s1.points[0].moments.eyy);
  // the parameters reach the model as 2D and 2Q: energy balance β E[Y²] = D + Q E[X²] at every
  // point (80x80 cells resolve it to ~1.5 %; a wrong factor 2 in the mapping would be 50 %)
  for (const auto& p : s1.points)
    CHECK(0.3 * p.moments.eyy == Approx(0.5 * p.parameters[0] + 0.5 * p.parameters[1] * p.moments.exx).epsilon(0.05));
  CHECK_THROWS_WITH(sweep(base, {{"k4x", {1.0}}}, req), Contains("unknown"));
}

TEST_CASE("sweep blocks: a block's points equal the same points of the whole sweep", "[fpk][sweep]") {
  // SweepOptions::block_first/last (vehs.dask.sweep): the grid envelope and the symbolic analysis
  // come from every point, so blocks merged point by point are the whole sweep, bitwise
  const vehs::Model base =
      fpk_fixtures::model(R"({"drift": {"x": 1, "x^3": -1, "y": -0.3}, "diffusion": {"1": 0.0194, "x^2": 0.0116}})");
  const std::vector<SweepAxis> axes = {{"2D", {0.015, 0.0194, 0.025}}, {"2Q", {0.008, 0.0116}}};
  GridRequest req;
  req.grid.x.n = req.grid.y.n = 80;
  const SweepResult whole = sweep(base, axes, req);
  for (const auto& [first, last] : std::vector<std::pair<std::size_t, std::size_t>>{{0, 2}, {2, 5}, {5, 6}, {4, 5}}) {
    SweepOptions o;
    o.block_first = first;
    o.block_last = last;
    const SweepResult part = sweep(base, axes, req, o);
    CHECK(part.grid.x.min == whole.grid.x.min);
    CHECK(part.grid.y.max == whole.grid.y.max);
    for (std::size_t k = 0; k < 6; ++k) {
      INFO("block [" << first << ", " << last << "), point " << k);
      if (k < first || k >= last) {
        CHECK(part.points[k].error == "outside the block");
        continue;
      }
      CHECK(part.points[k].error.empty());
      CHECK(part.points[k].moments.eyy == whole.points[k].moments.eyy);  // bitwise
      CHECK(part.points[k].moments.exx == whole.points[k].moments.exx);
      CHECK(part.points[k].boundary_mass == whole.points[k].boundary_mass);
    }
  }
}

TEST_CASE("sweep plans: one grid envelope and one analysis serve every block", "[fpk][sweep]") {
  // plan_sweep once (a Dask client), analyse_sweep once (a worker), the blocks solved with it:
  // the whole sweep's points, bitwise; a plan of another sweep is refused
  const vehs::Model base =
      fpk_fixtures::model(R"({"drift": {"x": 1, "x^3": -1, "y": -0.3}, "diffusion": {"1": 0.0194, "x^2": 0.0116}})");
  const std::vector<SweepAxis> axes = {{"2D", {0.015, 0.025}}, {"2Q", {0.008, 0.0116}}};
  GridRequest req;
  req.grid.x.n = req.grid.y.n = 80;
  const SweepResult whole = sweep(base, axes, req);
  SweepPlan plan = plan_sweep(base, axes, req);
  CHECK(plan.grid.x.min == whole.grid.x.min);
  CHECK(plan.grid.y.max == whole.grid.y.max);
  CHECK(plan.errors == std::vector<std::string>(4));
  CHECK(!plan.analysis);
  SweepPlan grid_only = plan;
  analyse_sweep(plan, base, axes);
  REQUIRE(plan.analysis);
  for (const SweepPlan* given : {&plan, &grid_only}) {  // without its analysis, the block makes it
    for (const auto& [first, last] : std::vector<std::pair<std::size_t, std::size_t>>{{0, 3}, {3, 4}}) {
      SweepOptions o;
      o.block_first = first;
      o.block_last = last;
      o.plan = given;
      const SweepResult part = sweep(base, axes, req, o);
      for (std::size_t k = first; k < last; ++k) {
        INFO("block [" << first << ", " << last << "), point " << k << ", analysed plan " << (given == &plan));
        CHECK(part.points[k].moments.eyy == whole.points[k].moments.eyy);  // bitwise
        CHECK(part.points[k].moments.exx == whole.points[k].moments.exx);
      }
    }
  }
  SweepOptions o;
  o.plan = &plan;
  CHECK_THROWS_WITH(sweep(base, {{"2D", {0.015, 0.02, 0.025}}}, req, o), Contains("the plan has 4 points, the sweep 3"));
}

TEST_CASE("parameters by name follow the contract's signs", "[fpk][sweep]") {
  vehs::Model m = fpk_fixtures::paper_learned();
  CHECK(vehs::get_parameter(m, "beta") == Approx(0.1010));
  CHECK(vehs::get_parameter(m, "k9") == Approx(3.1068));
  CHECK(vehs::get_parameter(m, "2Q") == Approx(0.0116));
  CHECK(vehs::get_parameter(m, "Q") == Approx(0.0058));
  vehs::set_parameter(m, "k7", -12.0);
  CHECK(m.drift_coef("x^7") == Approx(12.0));
  vehs::set_parameter(m, "drift[x^2*y]", -0.3);
  CHECK(m.drift_coef("x^2*y") == -0.3);
  vehs::set_parameter(m, "D", 0.01);
  CHECK(m.diffusion_coef("1") == Approx(0.02));
}

TEST_CASE("boundary mass is a probability mass (>= 0): an undershoot on the edges is kept apart", "[fpk][domain]") {
  // a hand-made density: the ring's cells hold +1e-9 and -3e-9 (the central scheme's noise where
  // the density has vanished), signed sum negative
  const FpkModel fm(fpk_fixtures::model(R"({"drift": {"x": 1, "x^3": -1, "y": -0.1}, "diffusion": {"1": 0.01}})"));
  StationaryResult r;
  r.grid.x = {-2.0, 2.0, 4};
  r.grid.y = {-1.0, 1.0, 4};
  const double area = r.grid.cell_area();
  r.density.assign(16, 0.0);
  r.density[r.grid.index(0, 0)] = 1e-9 / area;
  r.density[r.grid.index(3, 2)] = -3e-9 / area;
  for (int i : {1, 2})
    for (int j : {1, 2}) r.density[r.grid.index(i, j)] = (1.0 + 2e-9) / (4.0 * area);
  analyse_density(fm, r);
  CHECK(r.boundary_mass == Approx(1e-9).margin(1e-18));
  CHECK(r.boundary_undershoot == Approx(-3e-9).margin(1e-18));
  CHECK(r.boundary_signed_mass() == Approx(-2e-9).margin(1e-18));  // what the domain control tests

  // a new user's sweep (bistable, 2D in {0.01, 0.02} on one shared 100x100 grid) printed
  // boundary_mass -5.6e-09 for 2D = 0.01
  GridRequest req;
  req.grid.x.n = req.grid.y.n = 100;
  const SweepResult s = sweep(fpk_fixtures::model(R"({"drift": {"x": 1, "x^3": -1, "y": -0.1}, "diffusion": {"1": 0.02}})"),
                              {{"2D", {0.01, 0.02}}}, req);
  for (const auto& p : s.points) {
    INFO("2D = " << p.parameters[0] << ": " << p.error);
    CHECK(p.error.empty());
    CHECK(p.boundary_mass >= 0.0);
    CHECK(p.boundary_mass <= 1e-6);
  }
}
