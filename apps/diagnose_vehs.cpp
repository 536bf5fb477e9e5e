// diagnose-vehs: how well does a model reproduce measured displacement records, and where does it fail?
// All keys: --help (the key table of src/tools/diagnose_tool.cpp).
#include "tools/tools.hpp"

int main(int argc, char** argv) { return vehs::tools::diagnose_main(argc, argv); }
