#include "tools/data_checks.hpp"

#include <cmath>
#include <iostream>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/flat_stretches.hpp"
#include "vehs/core/glitches.hpp"

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

namespace {

std::string rule_of(const Config& c, const std::string& key) {
  const std::string rule = c.string_or(key, "error");
  if (rule != "error" && rule != "drop" && rule != "keep")
    c.fail(key, "must be \"error\", \"drop\" or \"keep\" (got \"" + rule + "\")");
  return rule;
}

/// What a check that found something does under its rule: "error" stops naming the findings
/// (`what`), "drop" cuts the records there (said on stderr even with --quiet).
template <class Drop>
Dataset apply_rule(const std::string& rule, const std::string& key, const Dataset& data, const std::string& what,
                   const Drop& drop) {
  if (rule == "error") throw Error(what + " (config '" + key + "': \"drop\" removes them, \"keep\" fits them)");
  std::cerr << "warning: dropped " << what << "\n";  // changes the data: said even with --quiet
  Dataset kept = drop(data);
  if (kept.records.empty()) throw Error("no record is left after dropping " + what);
  return kept;
}

Dataset without_flat_stretches(const Config& c, Dataset data) {
  const std::string rule = rule_of(c, "flat_stretches");
  if (rule == "keep") return data;
  const std::vector<FlatStretch> flat = find_flat_stretches(data);
  if (flat.empty()) return data;
  const std::string what = std::to_string(flat.size()) + " flat stretch" + (flat.size() > 1 ? "es" : "") +
                           " (one value repeated): " + describe_flat_stretches(data, flat);
  return apply_rule(rule, "flat_stretches", data, what,
                    [&](const Dataset& d) { return drop_flat_stretches(d, flat); });
}

Dataset without_glitches(const Config& c, Dataset data) {
  const std::string rule = rule_of(c, "glitches");
  if (rule == "keep") return data;
  const std::vector<Glitch> glitches = find_glitches(data);
  if (glitches.empty()) return data;
  const std::string what = std::to_string(glitches.size()) + " isolated glitch sample" +
                           (glitches.size() > 1 ? "s" : "") + ": " + describe_glitches(data, glitches);
  return apply_rule(rule, "glitches", data, what,
                    [&](const Dataset& d) { return drop_glitches(d, glitches); });
}

}  // namespace

Dataset checked_measurements(const Config& c, Dataset data) {
  if (!data.records.empty()) (void)data.common_dt();  // in the files' own units, before any scaling
  return without_glitches(c, without_flat_stretches(c, std::move(data)));
}

}  // namespace vehs::tools
