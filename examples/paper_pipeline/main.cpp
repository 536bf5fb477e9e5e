// The seed paper's pipeline in C++: simulate the penta-stable harvester (Eq. 27, the paper's
// scheme Eq. 30), identify drift and diffusion from x(t) alone, solve the stationary
// Fokker-Planck equation of the *learned* model, and print true vs learned parameters and the
// learned model's stationary moments.
//   paper_pipeline [RECORDS.csv MODEL.json]   also writes the records and the learned model
//                                             (the input of the diagnose_csv example)
// Exit status 0 when every learned parameter is within 5 standard errors of the truth.
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include <vehs/core/parameters.hpp>
#include <vehs/fpk/stationary.hpp>
#include <vehs/identify/identify.hpp>
#include <vehs/io/measurements.hpp>
#include <vehs/io/model_file.hpp>
#include <vehs/sim/simulate.hpp>

int main(int argc, char** argv) try {
  // b2 = -beta y - sum k_i x^i, a22 = 2D + 2Q x^2 (the model file stores the raw drift
  // coefficients: "x": -k1; docs/model-file.md)
  const vehs::Model truth =
      vehs::Model::paper(0.1, {{1, 1.0}, {3, -7.7}, {5, 16.3}, {7, -12.5}, {9, 3.1}}, 0.02, 0.01);

  vehs::sim::SimulationOptions sim;  // Eq. 30, x0 uniform in [-1.5, 1.5], seed 1
  sim.records = 20;
  sim.samples = 50000;
  sim.dt = 0.002;
  const vehs::Dataset data = vehs::sim::simulate(truth, sim);

  const vehs::identify::Result fit = vehs::identify::identify(data, vehs::identify::Options{});

  // every parameter of the truth, then any term the fit selected that the truth does not have
  std::map<std::string, vehs::PhysicalParameter> learned;
  for (const vehs::PhysicalParameter& p : vehs::physical_parameters(fit.model)) learned[p.name] = p;
  std::printf("%-8s %10s %12s %10s %8s\n", "param", "true", "learned", "stderr", "dev/se");
  int outliers = 0;  // |dev/se| >= 5: a missed, spurious or biased term (seed 1: deterministic)
  auto row = [&](const std::string& name, double t) {
    const auto it = learned.find(name);
    const double v = it == learned.end() ? 0.0 : it->second.value;
    const double se = it == learned.end() ? NAN : it->second.stderr_.value_or(NAN);
    const double z = (v - t) / se;
    if (!(std::abs(z) < 5.0)) ++outliers;
    std::printf("%-8s %10.4g %12.6g %10.2g %+8.2f\n", name.c_str(), t, v, se, z);
  };
  const auto truth_parameters = vehs::physical_parameters(truth);
  for (const vehs::PhysicalParameter& p : truth_parameters) row(p.name, p.value);
  for (const auto& [name, p] : learned)
    if (vehs::get_parameter(truth, name) == 0.0) row(name, 0.0);
  std::printf("estimator: %s, stride %d\n",
              vehs::enum_to_string(vehs::kEstimatorNames, fit.model.fit->estimator).c_str(), fit.model.fit->stride);

  vehs::fpk::GridRequest grid;  // automatic domain
  grid.grid.x.n = grid.grid.y.n = 200;
  const vehs::fpk::StationaryResult p =
      vehs::fpk::solve_with_domain(vehs::fpk::FpkModel(fit.model), grid, vehs::fpk::SolveOptions{});
  std::printf("learned model, stationary FPK on 200 x 200: E[X^2] = %.5f, E[Y^2] = %.5f "
              "(mean power is proportional to E[Y^2])\n",
              p.moments.exx, p.moments.eyy);

  if (argc == 3) {
    vehs::WriteColumns columns;
    columns.with_y = false;  // a sensor records x only
    columns.precision = 10;
    vehs::write_measurements(argv[1], data, columns);
    vehs::write_model_file(argv[2], fit.model);
    std::printf("wrote %s and %s\n", argv[1], argv[2]);
  }
  return outliers == 0 ? 0 : 1;
} catch (const vehs::Error& e) {
  std::fprintf(stderr, "paper_pipeline: %s\n", e.what());
  return 1;
}
