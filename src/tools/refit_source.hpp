#pragma once
// What `identify-vehs --refit FILE` runs: the next fit diagnose-vehs described, without a hand
// merge. FILE is either
//  * a diagnosis file (diagnose-vehs's `output` or its report's summary.json; it has `verdict`):
//    the identify-vehs config its `refit_file` names is run — as written, or, when that path does
//    not exist (the report folder was moved), the file of that name beside FILE; or
//  * the refit config itself (<report>/refit.json, any identify-vehs config; it has `data`), run
//    as it is.
// A diagnosis that recommends nothing (refit_config null), a refit config that is gone, or a file
// of neither kind is a one-line vehs::Error naming FILE.
#include <string>

namespace vehs::tools {

/// The path of the identify-vehs config to run for `file` (see above).
std::string refit_config_for(const std::string& file);

}  // namespace vehs::tools
