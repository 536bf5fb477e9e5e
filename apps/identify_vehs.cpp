// identify-vehs: learns drift and diffusion (with standard errors) from displacement records.
// All keys: --help (the key table of src/tools/identify_tool.cpp).
#include "tools/tools.hpp"

int main(int argc, char** argv) { return vehs::tools::identify_main(argc, argv); }
