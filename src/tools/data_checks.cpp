#include "tools/data_checks.hpp"

#include <cmath>
#include <iostream>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
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

Dataset checked_measurements(const Config& c, Dataset data) {
  const std::string rule = c.string_or("glitches", "error");
  if (rule != "error" && rule != "drop" && rule != "keep")
    c.fail("glitches", "must be \"error\", \"drop\" or \"keep\" (got \"" + rule + "\")");
  if (rule == "keep") return data;
  const std::vector<Glitch> glitches = find_glitches(data);
  if (glitches.empty()) return data;
  const std::string what = std::to_string(glitches.size()) + " isolated glitch sample" +
                           (glitches.size() > 1 ? "s" : "") + ": " + describe_glitches(data, glitches);
  if (rule == "error")
    throw Error(what + " (config 'glitches': \"drop\" removes them, \"keep\" fits them)");
  std::cerr << "warning: dropped " << what << "\n";  // changes the data: said even with --quiet
  Dataset kept = drop_glitches(data, glitches);
  if (kept.records.empty()) throw Error("no record is left after dropping " + what);
  return kept;
}

}  // namespace vehs::tools
