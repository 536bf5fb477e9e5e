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
          "signature at i-1 and i+1): \"error\" stops naming their lines, \"drop\" cuts each record at its "
          "glitches (the pieces are fitted as separate records; pieces under 16 samples are left out), "
          "\"keep\" fits them as data.",
          "\"error\""};
}

KeySpec flat_stretches_key_spec() {
  return {"flat_stretches", "\"error\" | \"drop\" | \"keep\"",
          "Flat stretches: runs of one exactly repeated value of x longer than the record's own repeats "
          "explain (a dropout logged as 0 or as the last value, a stuck or saturated sensor; a run of L "
          "samples when N p^(L-1) < 1e-9 and L >= 5, p the record's share of equal consecutive samples, "
          "N its length; quantised records, with 1 in 1000 consecutive pairs repeated in shorter runs, are "
          "not checked): \"error\" stops naming their lines, \"drop\" cuts each record there (as for "
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

/// One check under its key: "keep" returns the data; else `find` the bad samples, and with
/// "error" stop naming them, with "drop" cut the records there (said on stderr even with --quiet).
template <class Found, class Drop>
Dataset apply_rule(const Config& c, const std::string& key, Dataset data, const Found& found,
                   const std::string& what, const Drop& drop) {
  if (rule_of(c, key) == "keep" || found.empty()) return data;
  if (rule_of(c, key) == "error")
    throw Error(what + " (config '" + key + "': \"drop\" removes them, \"keep\" fits them)");
  std::cerr << "warning: dropped " << what << "\n";  // changes the data: said even with --quiet
  Dataset kept = drop(data);
  if (kept.records.empty()) throw Error("no record is left after dropping " + what);
  return kept;
}

Dataset without_flat_stretches(const Config& c, Dataset data) {
  if (rule_of(c, "flat_stretches") == "keep") return data;
  const std::vector<FlatStretch> flat = find_flat_stretches(data);
  const std::string what = std::to_string(flat.size()) + " flat stretch" + (flat.size() > 1 ? "es" : "") +
                           " (one value repeated): " + (flat.empty() ? "" : describe_flat_stretches(data, flat));
  return apply_rule(c, "flat_stretches", std::move(data), flat, what,
                    [&](const Dataset& d) { return drop_flat_stretches(d, flat); });
}

Dataset without_glitches(const Config& c, Dataset data) {
  if (rule_of(c, "glitches") == "keep") return data;
  const std::vector<Glitch> glitches = find_glitches(data);
  const std::string what = std::to_string(glitches.size()) + " isolated glitch sample" +
                           (glitches.size() > 1 ? "s" : "") + ": " + (glitches.empty() ? "" : describe_glitches(data, glitches));
  return apply_rule(c, "glitches", std::move(data), glitches, what,
                    [&](const Dataset& d) { return drop_glitches(d, glitches); });
}

}  // namespace

Dataset checked_measurements(const Config& c, Dataset data) {
  if (!data.records.empty()) (void)data.common_dt();  // in the files' own units, before any scaling
  return without_glitches(c, without_flat_stretches(c, std::move(data)));
}

}  // namespace vehs::tools
