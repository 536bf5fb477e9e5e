// libFuzzer target: a config file as the tools read it (vehs/io/json_file.hpp: nesting cap, NUL
// bytes, trailing content, one-line errors), then the key checks and every typed getter of the
// tools' Config (tools/config.hpp) on every key the document has, and on its sub-objects. Any
// vehs::Error is a correct answer; a crash, sanitizer report, hang or another exception is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tools/config.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/json_file.hpp"

namespace {

void exercise(const vehs::tools::Config& c, int depth) {
  std::vector<std::string> keys;
  for (auto it = c.json().begin(); it != c.json().end(); ++it) keys.push_back(it.key());
  try {
    c.check_keys({"model", "data", "output", "grid", "x", "y"});  // "did you mean" on every other key
  } catch (const vehs::Error&) {
  }
  for (const auto& k : keys) {
    try { (void)c.number(k); } catch (const vehs::Error&) {}
    try { (void)c.integer(k); } catch (const vehs::Error&) {}
    try { (void)c.positive(k); } catch (const vehs::Error&) {}
    try { (void)c.non_negative_or(k, 0.0); } catch (const vehs::Error&) {}
    try { (void)c.integer_at_least(k, 1, 1); } catch (const vehs::Error&) {}
    try { (void)c.boolean_or(k, false); } catch (const vehs::Error&) {}
    try { (void)c.string(k); } catch (const vehs::Error&) {}
    try { (void)c.string_list(k); } catch (const vehs::Error&) {}
    try {
      const vehs::tools::Config sub = c.object(k);
      if (depth < 3) exercise(sub, depth + 1);
    } catch (const vehs::Error&) {
    }
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
  (void)vehs::json_excerpt(j);
  if (!j.is_object()) return 0;
  vehs::tools::Config c(j, "fuzz.json");
  exercise(c, 0);
  try {  // --set overrides: a value from the command line
    vehs::tools::ConfigSchema schema;
    schema.keys.push_back({"grid", "object", "", "", true});
    c.set_override("grid=" + text.substr(0, 256), schema);
  } catch (const vehs::Error&) {
  }
  return 0;
}
