// A user's program against the installed package: builds a model in C++ (no JSON), solves its
// stationary Fokker-Planck equation and simulates it, and checks both against the exact
// E[X^2] of a linear oscillator; exits 0 on success.
#include <cmath>
#include <cstdio>

#include <vehs/vehs.hpp>

int main() {
  // linear oscillator dX = Y dt, dY = (-k1 X - beta Y) dt + sqrt(2D) dB: E[X^2] = D / (beta k1)
  const double beta = 0.5, k1 = 1.0, two_d = 0.2;
  const vehs::Model model = vehs::ModelBuilder("consumer model")
                                .parameter("beta", beta)
                                .parameter("k1", k1)
                                .diffusion("1", two_d)
                                .build();
  const double exact = 0.5 * two_d / (beta * k1);

  vehs::fpk::GridRequest grid;
  grid.grid.x.n = 120;
  grid.grid.y.n = 120;
  const vehs::fpk::StationaryResult fpk =
      vehs::fpk::solve_with_domain(vehs::fpk::FpkModel(model), grid, vehs::fpk::SolveOptions{});

  vehs::sim::SimulationOptions sim;
  sim.records = 32;
  sim.samples = 20000;
  sim.dt = 0.05;
  sim.substeps = 5;
  sim.scheme = vehs::sim::Scheme::Taylor15;
  sim.burn_in = 20.0;
  vehs::sim::StatisticsOptions stats;
  const auto mc = vehs::sim::simulate_statistics(model, sim, stats);
  const vehs::Estimate ex2 = mc.moment("E[X^2]");

  std::printf("E[X^2]: exact %.4f, FPK %.4f, Monte Carlo %.4f +- %.4f\n", exact, fpk.moments.exx, ex2.value,
              ex2.stderr_);
  // the discretisation error is O(h^2): 0.35% on this 120 x 120 grid (0.1% on 240 x 240)
  const bool fpk_ok = std::abs(fpk.moments.exx - exact) < 1e-2 * exact;
  const bool mc_ok = std::abs(ex2.value - exact) < 5.0 * ex2.stderr_;  // false failure ~6e-7
  return fpk_ok && mc_ok ? 0 : 1;
}
