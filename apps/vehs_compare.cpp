// vehs-compare: learned vs true (and paper-reported) parameters with standard errors.
// All keys: --help (the key table of src/tools/compare_tool.cpp).
#include "tools/tools.hpp"

int main(int argc, char** argv) { return vehs::tools::compare_main(argc, argv); }
