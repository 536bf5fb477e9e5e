#pragma once
// A driven linear oscillator (β 0.2, k 1, the input's gain 0.5), sampled at dt from Taylor 1.5 with
// 40 internal steps, white sensor noise 0.01, the input an AR(1) sequence held over each interval
// (a small LCG: the input is not the simulator's noise).
#include <cstdint>
#include <vector>

#include "vehs/io/model_file.hpp"
#include "vehs/sim/simulate.hpp"

namespace fit_test {

inline vehs::Dataset driven(double dt, std::size_t n, std::uint64_t seed) {
  const vehs::Model truth = vehs::model_from_json(
      nlohmann::json::parse(R"({"drift": {"x": -1.0, "y": -0.2, "u": 0.5}, "diffusion": {"1": 0.02}})"), "truth");
  std::vector<double> u(n);
  std::uint64_t s = seed * 2654435761u + 1;
  double prev = 0.0;
  for (double& v : u) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    v = prev = 0.5 * prev + 2.0 * (double(s >> 11) / double(1ULL << 53) - 0.5);
  }
  vehs::sim::SimulationOptions o;
  o.dt = dt;
  o.substeps = 40;
  o.samples = n;
  o.records = 1;
  o.seed = seed;
  o.scheme = vehs::sim::Scheme::Taylor15;
  o.sensor_noise = 0.01;
  o.record_y = false;
  o.drive = u;
  return vehs::sim::simulate(truth, o);
}

}  // namespace fit_test
