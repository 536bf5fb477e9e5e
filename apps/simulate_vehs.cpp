// simulate-vehs: ensembles of records of a vehs model, sampled like a sensor, with optional
// Monte Carlo statistics. All keys: simulate-vehs --help (table in src/sim/config.cpp).
#include "vehs/sim/config.hpp"

int main(int argc, char** argv) {
  return vehs::run_app(argc, argv, vehs::sim::simulate_schema(),
                       [](vehs::Config& config, const vehs::AppOptions& app) {
                         return vehs::sim::run_simulate_job(vehs::sim::simulate_job_from_config(config), app);
                       });
}
