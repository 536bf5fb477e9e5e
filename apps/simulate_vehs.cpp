// simulate-vehs: ensembles of records of a vehs model, sampled like a sensor, with optional Monte Carlo statistics.
// All keys: --help (the key table of src/tools/simulate_tool.cpp).
#include "tools/tools.hpp"

int main(int argc, char** argv) { return vehs::tools::simulate_main(argc, argv); }
