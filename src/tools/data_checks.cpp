#include "tools/data_checks.hpp"

#include <iostream>
#include <utility>

#include "vehs/fit/data_checks.hpp"

namespace vehs::tools {

KeySpec glitches_key_spec() {
  return {"glitches", "\"error\" | \"drop\" | \"keep\"",
          "Isolated glitch samples (one sample far off the line through its neighbours: |x_i - (x_{i-1} + "
          "x_{i+1})/2| > 12 robust standard deviations of that quantity, with the one-displaced-sample "
          "signature at i-1 and i+1; a record's first and last samples are tested one-sided, against the line through "
          "their next two samples): \"error\" stops naming their lines, \"drop\" cuts each record at its "
          "glitches (the pieces are fitted as separate records; pieces under 16 samples are left out), "
          "\"keep\" fits them as data.",
          "\"error\""};
}

KeySpec flat_stretches_key_spec() {
  return {"flat_stretches", "\"error\" | \"drop\" | \"keep\"",
          "Flat stretches: runs of one exactly repeated value of x longer than the record's own repeats "
          "explain (a dropout logged as 0 or as the last value, a stuck or saturated sensor; a run of L "
          "samples when N p^(L-1) < 1e-9 and L >= 5, p the record's share of equal consecutive samples, "
          "N its length; quantised records (1 in 1000 consecutive pairs repeated in shorter runs, or most "
          "pairs equal) are checked for clipping (every run at the record's extreme value when that value holds "
          "more than 3x the samples of the next value plus 30, in at least 3 runs or one 3x longer than any other "
          "run) and for runs entered or left by a jump (a step into or out of the run larger than 3 grid steps "
          "and 4x every increment within max(L, 16) samples around it: a dropout, a reading held while the "
          "signal moved)): \"error\" stops naming their lines, \"drop\" cuts each record there (as for "
          "glitches), \"keep\" fits them as data.",
          "\"error\""};
}

DataChecks data_checks(const Config& c) {
  DataChecks d;
  for (auto [key, rule] : {std::pair{"glitches", &d.glitches}, std::pair{"flat_stretches", &d.flat_stretches}}) {
    const std::string text = c.string_or(key, "error");
    if (text != "error" && text != "drop" && text != "keep")
      c.fail(key, "must be \"error\", \"drop\" or \"keep\" (got \"" + text + "\")");
    *rule = enum_from_string(kCheckRuleNames, text, key);
  }
  return d;
}

Dataset checked_measurements(const Config& c, Dataset data) {
  const DataChecks checks = data_checks(c);
  CheckedData checked = check_data(std::move(data), checks);
  for (const std::string& line : checked.dropped)
    std::cerr << "warning: " << line << "\n";  // changes the data: said even with --quiet
  return std::move(checked.data);
}

}  // namespace vehs::tools
