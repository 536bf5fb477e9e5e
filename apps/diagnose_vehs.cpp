// diagnose-vehs: how well does a model reproduce measured displacement records, and where does
// it fail? See include/vehs/diagnose/diagnose.hpp and `diagnose-vehs --help`.
#include "vehs/diagnose/app.hpp"

int main(int argc, char** argv) { return vehs::diagnose::main(argc, argv); }
