// libFuzzer target: a model file (vehs/io/model_file.hpp: terms, coefficients, effects, stderr,
// fit sections) from JSON text, then the model's own checks and its round trip to JSON. Any
// vehs::Error is a correct answer; a crash, sanitizer report, hang or another exception is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/io/json_file.hpp"
#include "vehs/io/model_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const nlohmann::json j = vehs::parse_json_text(text, "model.json");
    nlohmann::ordered_json sections;
    const vehs::Model m = vehs::model_from_json(j, "model.json", &sections);
    (void)vehs::model_to_json(m, sections).dump();
  } catch (const vehs::Error&) {
  }
  return 0;
}
