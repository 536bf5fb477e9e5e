#pragma once
// The five executables: each apps/<name>.cpp is `int main(argc, argv) { return <tool>_main(argc,
// argv); }`, and each <tool>_main is run_app(schema, body) of its <tool>_tool.hpp.
namespace vehs::tools {

int simulate_main(int argc, char** argv);  ///< simulate-vehs
int identify_main(int argc, char** argv);  ///< identify-vehs
int fpk_main(int argc, char** argv);       ///< fpk-stationary
int diagnose_main(int argc, char** argv);  ///< diagnose-vehs
int compare_main(int argc, char** argv);   ///< vehs-compare

}  // namespace vehs::tools
