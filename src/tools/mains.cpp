// The entry points of the executables: one line each, the same pattern for all.
#include "tools/compare_tool.hpp"
#include "tools/diagnose_tool.hpp"
#include "tools/fpk_tool.hpp"
#include "tools/identify_tool.hpp"
#include "tools/simulate_tool.hpp"
#include "tools/tools.hpp"

namespace vehs::tools {

int simulate_main(int argc, char** argv) { return run_app(argc, argv, simulate_schema(), run_simulate); }
int identify_main(int argc, char** argv) { return run_app(argc, argv, identify_schema(), run_identify); }
int fpk_main(int argc, char** argv) { return run_app(argc, argv, fpk_schema(), run_fpk); }
int diagnose_main(int argc, char** argv) { return run_app(argc, argv, diagnose_schema(), run_diagnose); }
int compare_main(int argc, char** argv) { return run_app(argc, argv, compare_schema(), run_compare); }

}  // namespace vehs::tools
