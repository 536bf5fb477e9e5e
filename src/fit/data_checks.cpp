#include "vehs/fit/data_checks.hpp"

#include "vehs/core/error.hpp"
#include "vehs/core/flat_stretches.hpp"
#include "vehs/core/glitches.hpp"

namespace vehs {

namespace {

/// What a check that found something (`what`) does under its rule: Error stops naming the
/// findings, Drop cuts the records there and says so in `out.dropped`.
template <class Drop>
void apply_rule(CheckRule rule, const std::string& option, const std::string& what, const Drop& drop,
                CheckedData& out) {
  if (rule == CheckRule::Error)
    throw Error(what + " (config '" + option + "': \"drop\" removes them, \"keep\" fits them)");
  out.data = drop(out.data);
  out.dropped.push_back("dropped " + what);
  if (out.data.records.empty()) throw Error("no record is left after dropping " + what);
}

void flat_stretches(CheckRule rule, CheckedData& out) {
  if (rule == CheckRule::Keep) return;
  const std::vector<FlatStretch> flat = find_flat_stretches(out.data);
  if (flat.empty()) return;
  const std::string what = std::to_string(flat.size()) + " flat stretch" + (flat.size() > 1 ? "es" : "") +
                           " (one value repeated): " + describe_flat_stretches(out.data, flat);
  apply_rule(rule, "flat_stretches", what, [&](const Dataset& d) { return drop_flat_stretches(d, flat); }, out);
}

void glitches(CheckRule rule, CheckedData& out) {
  if (rule == CheckRule::Keep) return;
  const std::vector<Glitch> found = find_glitches(out.data);
  if (found.empty()) return;
  const std::string what = std::to_string(found.size()) + " isolated glitch sample" + (found.size() > 1 ? "s" : "") +
                           ": " + describe_glitches(out.data, found);
  apply_rule(rule, "glitches", what, [&](const Dataset& d) { return drop_glitches(d, found); }, out);
}

}  // namespace

CheckedData check_data(Dataset data, const DataChecks& checks) {
  if (!data.records.empty()) (void)data.common_dt();  // in the files' own units, before any scaling
  CheckedData out{std::move(data), {}};
  flat_stretches(checks.flat_stretches, out);
  glitches(checks.glitches, out);
  return out;
}

}  // namespace vehs
