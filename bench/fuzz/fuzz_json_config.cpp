// libFuzzer target: a config file as the tools read it (vehs/io/json_file.hpp: nesting cap,
// trailing content, one-line errors), then every tool's key table and typed getters
// (tools/config.hpp). Any vehs::Error is a correct answer; a crash, sanitizer report, hang or
// another exception is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "tools/compare_tool.hpp"
#include "tools/config.hpp"
#include "tools/diagnose_tool.hpp"
#include "tools/fpk_tool.hpp"
#include "tools/identify_tool.hpp"
#include "tools/simulate_tool.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/json_file.hpp"

namespace {

void exercise(const vehs::tools::Config& c, const vehs::tools::ConfigSchema& schema) {
  std::vector<std::string> allowed;
  for (const auto& k : schema.keys) allowed.push_back(k.name);
  try {
    c.check_keys(allowed);
  } catch (const vehs::Error&) {
  }
  for (const auto& k : schema.keys) {
    if (!c.has(k.name)) continue;
    // every getter on every key: wrong types must give one-line errors
    try { (void)c.number(k.name); } catch (const vehs::Error&) {}
    try { (void)c.integer(k.name); } catch (const vehs::Error&) {}
    try { (void)c.positive(k.name); } catch (const vehs::Error&) {}
    try { (void)c.boolean_or(k.name, false); } catch (const vehs::Error&) {}
    try { (void)c.string(k.name); } catch (const vehs::Error&) {}
    try { (void)c.string_list(k.name); } catch (const vehs::Error&) {}
    try { (void)c.object(k.name); } catch (const vehs::Error&) {}
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  nlohmann::json j;
  try {
    j = vehs::parse_json_text(text, "fuzz.json");
  } catch (const vehs::Error&) {
    return 0;
  }
  if (!j.is_object()) return 0;
  const vehs::tools::Config c(j, "fuzz.json");
  for (const auto* schema : {&vehs::tools::simulate_schema(), &vehs::tools::identify_schema(),
                             &vehs::tools::fpk_schema(), &vehs::tools::diagnose_schema(),
                             &vehs::tools::compare_schema()})
    exercise(c, *schema);
  (void)vehs::json_excerpt(j);
  return 0;
}
