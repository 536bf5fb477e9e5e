// The entry points of the executables: the same pattern for all (identify-vehs also takes --refit).
#include "tools/compare_tool.hpp"
#include "tools/diagnose_tool.hpp"
#include "tools/fpk_tool.hpp"
#include "tools/identify_tool.hpp"
#include "tools/refit_source.hpp"
#include "tools/simulate_tool.hpp"
#include "tools/tools.hpp"

namespace vehs::tools {

int simulate_main(int argc, char** argv) { return run_app(argc, argv, simulate_schema(), run_simulate); }
int identify_main(int argc, char** argv) {
  static const ConfigOption refit{
      "--refit",
      "FILE instead of CONFIG: run the refit diagnose-vehs describes. FILE is its diagnosis (output or "
      "summary.json; the config named by its refit_file is run) or that config (<report>/refit.json), "
      "run as it is; --set applies on top. A diagnosis that recommends nothing is an error.",
      refit_config_for};
  return run_app(argc, argv, identify_schema(), run_identify, &refit);
}
int fpk_main(int argc, char** argv) { return run_app(argc, argv, fpk_schema(), run_fpk); }
int diagnose_main(int argc, char** argv) { return run_app(argc, argv, diagnose_schema(), run_diagnose); }
int compare_main(int argc, char** argv) { return run_app(argc, argv, compare_schema(), run_compare); }

}  // namespace vehs::tools
