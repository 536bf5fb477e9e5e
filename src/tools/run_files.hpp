#pragma once
// A run's files as its config names them: inputs (every string value naming an existing file,
// outside the output keys) are protected in the output transaction, so that no output can
// overwrite them; outputs (keys `output`, `summary`, `density`, `sweep_table`, `history`, `px`,
// `py`, `pxy`; folders `figures`, `report`) are checked before the work starts; the same file
// listed twice in one list (e.g. `data`) is an error (it would count its samples twice).
#include "tools/config.hpp"
#include "vehs/io/output_transaction.hpp"

namespace vehs::tools {

void declare_run_files(const Config& config, OutputTransaction& transaction);

}  // namespace vehs::tools
