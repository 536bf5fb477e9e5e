// fpk-stationary: stationary density of the model SDE from its Fokker–Planck equation.
// All keys: --help (the key table of src/tools/fpk_tool.cpp).
#include "tools/tools.hpp"

int main(int argc, char** argv) { return vehs::tools::fpk_main(argc, argv); }
