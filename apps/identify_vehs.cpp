// identify-vehs: learns drift and diffusion (with standard errors) from displacement records.
// All logic lives in the library (vehs/identify/app.hpp) so that tests can run it in-process.
#include "vehs/identify/app.hpp"

int main(int argc, char** argv) { return vehs::identify::main(argc, argv); }
