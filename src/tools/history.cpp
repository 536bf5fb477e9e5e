#include "tools/history.hpp"

#include <chrono>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "vehs/io/atomic_file.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/json_file.hpp"
#include "vehs/io/output_transaction.hpp"

namespace vehs::tools {

namespace {

struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      h ^= c[i];
      h *= 1099511628211ull;
    }
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  std::string hex() const {
    std::ostringstream os;
    os << std::hex << std::setw(16) << std::setfill('0') << h;
    return os.str();
  }
};

std::string now_iso() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::ostringstream os;
  os << std::put_time(&tm, "%Y-%m-%dT%H:%M:%SZ");
  return os.str();
}

}  // namespace

std::string data_fingerprint(const Dataset& data) {
  Fnv f;
  f.value(data.records.size());
  for (const auto& r : data.records) {
    f.value(r.size);
    f.value(r.dt);
    const double* x = data.x_of(r);
    const std::size_t step = std::max<std::size_t>(1, r.size / 64);
    for (std::size_t i = 0; i < r.size; i += step) f.value(x[i]);
    f.value(x[r.size - 1]);
  }
  return f.hex();
}

std::string model_hash(const Model& model) {
  Model m;
  m.drift = model.drift;
  m.diffusion = model.diffusion;
  m.effects = model.effects;
  const std::string s = model_to_json(m).dump();
  Fnv f;
  f.bytes(s.data(), s.size());
  return f.hex();
}

nlohmann::ordered_json history_entry(const Model& model, const std::string& model_file, const std::string& label,
                                     const Dataset& data, const diagnose::Result& result,
                                     const nlohmann::ordered_json& model_sections) {
  nlohmann::ordered_json e;
  e["time"] = now_iso();
  e["label"] = label;
  e["model_file"] = model_file;
  e["model_hash"] = model_hash(model);
  e["model"] = model_to_json(model, model_sections);  // the model itself: the history stays readable when files move
  nlohmann::ordered_json terms = nlohmann::ordered_json::array(), dterms = nlohmann::ordered_json::array();
  for (const auto& tc : model.drift) terms.push_back(tc.term.name());
  for (const auto& tc : model.diffusion) dterms.push_back(tc.term.name());
  nlohmann::ordered_json effects = nlohmann::ordered_json::array();
  for (const auto& ef : model.effects) effects.push_back(ef.name());
  e["drift_terms"] = terms;
  e["diffusion_terms"] = dterms;
  e["effects"] = effects;
  e["data_fingerprint"] = data_fingerprint(data);
  e["samples"] = data.total_samples();
  e["verdict"] = enum_to_string(diagnose::kVerdictNames, result.verdict);
  e["score"] = result.score;
  nlohmann::ordered_json comp = nlohmann::ordered_json::object();
  for (const auto& c : result.components)
    comp[c.name] = c.test.available ? nlohmann::ordered_json(c.test.excess) : nlohmann::ordered_json();
  e["components"] = comp;
  return e;
}

std::vector<nlohmann::ordered_json> read_history(const std::string& path) {
  std::vector<nlohmann::ordered_json> out;
  const std::string folder = std::filesystem::path(path).parent_path().string();
  recover_stale_outputs(folder.empty() ? "." : folder);  // a killed run's history is completed or removed first
  if (!std::filesystem::exists(path)) return out;
  const std::string text = read_text_file(path, "history file");  // read, not protected: it is also an output
  nlohmann::ordered_json j;
  try {
    check_json_text(text, path);
    j = nlohmann::ordered_json::parse(text);
  } catch (const std::exception& e) {
    throw Error(path + ": not a valid history file (" + std::string(e.what()) +
                "); move it away or name another file with 'history'");
  }
  if (!j.is_object() || !j.contains("entries") || !j["entries"].is_array())
    throw Error(path + ": not a history file (expected {\"entries\": [...]}); move it away or name another file with 'history'");
  for (const auto& e : j["entries"]) {
    if (!e.is_object() || !e.contains("score") || !e["score"].is_number())
      throw Error(path + ": a history entry without a numeric 'score'");
    out.push_back(e);
  }
  return out;
}

std::vector<nlohmann::ordered_json> append_history(const std::string& path, nlohmann::ordered_json entry) {
  // another run appending to the same file waits here until this run's outputs are committed
  if (OutputTransaction* t = OutputTransaction::active()) t->lock_output(path);
  auto entries = read_history(path);
  int version = 1;
  for (const auto& e : entries)
    if (e.value("data_fingerprint", "") == entry.value("data_fingerprint", "")) ++version;
  nlohmann::ordered_json numbered;
  numbered["version"] = version;
  for (auto it = entry.begin(); it != entry.end(); ++it) numbered[it.key()] = it.value();
  entries.push_back(numbered);
  nlohmann::ordered_json j;
  j["description"] =
      "diagnose-vehs model history: one entry per run; scores are comparable between entries with "
      "the same data_fingerprint (lower is better)";
  j["entries"] = entries;
  write_json_atomically(path, j);
  return entries;
}

}  // namespace vehs::tools
