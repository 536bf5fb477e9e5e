#pragma once
// The checks of measurement data before a fit: isolated glitch samples (vehs/core/glitches.hpp)
// and flat stretches (vehs/core/flat_stretches.hpp). Each has a rule: Error (the default: stop,
// naming the rows), Drop (cut the records there: the pieces are fitted as separate records) or
// Keep (data with genuine single-sample spikes or repeats). identify-vehs, diagnose-vehs and the
// Python package apply the same checks with the same messages.
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/enum_names.hpp"

namespace vehs {

enum class CheckRule { Error, Drop, Keep };
inline constexpr EnumNames<CheckRule, 3> kCheckRuleNames{
    {{CheckRule::Error, "error"}, {CheckRule::Drop, "drop"}, {CheckRule::Keep, "keep"}}};

struct DataChecks {
  CheckRule glitches = CheckRule::Error;        ///< option (config key) `glitches`
  CheckRule flat_stretches = CheckRule::Error;  ///< option (config key) `flat_stretches`
};

struct CheckedData {
  Dataset data;                       ///< the data to fit
  std::vector<std::string> dropped;   ///< one line per Drop rule that cut the data: what was dropped
};

/// Applies the checks to freshly read `data` (flat stretches first, then glitches); throws a
/// one-line vehs::Error under an Error rule that found something, naming the rows and the option.
CheckedData check_data(Dataset data, const DataChecks& checks);

}  // namespace vehs
