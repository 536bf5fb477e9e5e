#include "tools/config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>
#include <unistd.h>

#include "tools/file_globs.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/json_file.hpp"
#include "vehs/io/path_text.hpp"

namespace vehs::tools {

namespace {

// Levenshtein distance for "did you mean" suggestions.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string suggestion(const std::string& key, const std::vector<std::string>& allowed) {
  std::string best;
  std::size_t best_d = 4;
  for (const auto& k : allowed) {
    const std::size_t d = edit_distance(key, k);
    if (d < best_d) best_d = d, best = k;
  }
  if (!best.empty()) return " (did you mean '" + best + "'?)";
  std::string all;
  for (const auto& k : allowed) all += (all.empty() ? "" : ", ") + k;
  return " (allowed: " + all + ")";
}

std::string type_name(const nlohmann::json& v) { return json_excerpt(v); }

}  // namespace

std::string ConfigSchema::help_text() const {
  std::ostringstream os;
  os << "Config keys (JSON object; unknown keys are rejected):\n";
  for (const auto& k : keys) {
    os << "  " << k.name << "  (" << k.type;
    if (!k.default_text.empty())
      os << ", default " << k.default_text;
    else if (k.optional)
      os << ", optional";
    else
      os << ", required";
    os << ")\n";
    // wrap help at ~90 columns, indented
    std::istringstream words(k.help);
    std::string w, line = "      ";
    while (words >> w) {
      if (line.size() + w.size() + 1 > 92) {
        os << line << "\n";
        line = "      ";
      }
      line += (line.size() > 6 ? " " : "") + w;
    }
    if (line.size() > 6) os << line << "\n";
  }
  if (!epilog.empty()) os << "\n" << epilog << "\n";
  return os.str();
}

ConfigSchema with_keys_after(const std::string& after, const std::vector<KeySpec>& keys, ConfigSchema schema) {
  auto at = std::find_if(schema.keys.begin(), schema.keys.end(), [&](const KeySpec& k) { return k.name == after; });
  if (at != schema.keys.end()) ++at;
  schema.keys.insert(at, keys.begin(), keys.end());
  return schema;
}

const KeySpec* ConfigSchema::find(const std::string& key) const {
  for (const auto& k : keys)
    if (k.name == key) return &k;
  return nullptr;
}

Config::Config(nlohmann::json value, std::string file, std::string path)
    : value_(std::move(value)), file_(std::move(file)), path_(std::move(path)) {}

const std::vector<std::string>& measurement_file_keys() {
  static const std::vector<std::string> keys{"data",   "columns", "mat_variable", "dt",           "sampling",
                                             "detrend", "units",   "glitches",     "flat_stretches"};
  return keys;
}

void include_measurement_file(nlohmann::json& j, const std::string& file, const ConfigSchema& schema) {
  if (!j.contains("measurement") || !schema.find("measurement")) return;
  const nlohmann::json& name = j["measurement"];
  if (!name.is_string()) throw Error(file + ": 'measurement' must be the path of a measurement file (a string)");
  const std::string path = name.get<std::string>();
  check_path_text(path, file + ": 'measurement'");
  const nlohmann::json m = read_json_file(path, "measurement file");
  if (!m.is_object()) throw Error(path + ": a measurement file must be a JSON object");
  const auto& allowed = measurement_file_keys();
  for (auto it = m.begin(); it != m.end(); ++it) {
    if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end() || !schema.find(it.key()))
      throw Error(path + ": unknown key '" + it.key() + "' in a measurement file (it holds data, columns, "
                  "mat_variable, dt, sampling, detrend, units, glitches, flat_stretches)" + suggestion(it.key(), allowed));
    if (!j.contains(it.key())) j[it.key()] = it.value();  // the config's own value wins
  }
}

Config Config::load(const std::string& file, const ConfigSchema& schema) {
  nlohmann::json j = read_json_file(file, "config file");
  if (!j.is_object()) throw Error(file + ": a config must be a JSON object");
  include_measurement_file(j, file, schema);
  Config c(std::move(j), file);
  std::vector<std::string> allowed;
  for (const auto& k : schema.keys) allowed.push_back(k.name);
  c.check_keys(allowed);
  for (const auto& k : schema.keys)
    if (k.default_text.empty() && !k.optional && !c.has(k.name))
      throw Error(file + ": missing required key '" + k.name + "' (" + k.help.substr(0, 80) +
                  ")");
  return c;
}

void Config::set_override(const std::string& assignment, const ConfigSchema& schema) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw Error("--set expects key=value (got '" + assignment + "')");
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  if (!schema.find(key)) {
    std::vector<std::string> allowed;
    for (const auto& k : schema.keys) allowed.push_back(k.name);
    throw Error("--set: unknown key '" + key + "'" + suggestion(key, allowed));
  }
  nlohmann::json v;
  if (!text.empty() && (text.front() == '[' || text.front() == '{')) {
    v = parse_json_text(text, "--set " + key);  // a list or object must be valid JSON
  } else {
    try {
      v = parse_json_text(text, "--set " + key);
    } catch (const Error&) {
      v = text;  // bare strings need no quotes
    }
  }
  value_[key] = v;
}

bool Config::has(const std::string& key) const { return value_.contains(key); }

const nlohmann::json& Config::raw(const std::string& key) const {
  if (!value_.contains(key)) fail(key, "is missing");
  return value_.at(key);
}

std::string Config::where(const std::string& key) const {
  return file_ + ": '" + (path_.empty() ? key : path_ + "." + key) + "'";
}

void Config::fail(const std::string& key, const std::string& message) const {
  throw Error(where(key) + " " + message);
}

double Config::number(const std::string& key) const {
  const auto& v = raw(key);
  if (!v.is_number()) fail(key, "must be a number (got " + type_name(v) + ")");
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(key, "must be finite");
  return d;
}

double Config::number_or(const std::string& key, double fallback) const {
  return has(key) ? number(key) : fallback;
}

double Config::positive(const std::string& key) const {
  const double d = number(key);
  if (!(d > 0.0)) fail(key, "must be > 0 (got " + type_name(raw(key)) + ")");
  return d;
}

double Config::positive_or(const std::string& key, double fallback) const {
  return has(key) ? positive(key) : fallback;
}

double Config::non_negative_or(const std::string& key, double fallback) const {
  if (!has(key)) return fallback;
  const double d = number(key);
  if (d < 0.0) fail(key, "must be >= 0 (got " + type_name(raw(key)) + ")");
  return d;
}

std::optional<long long> json_integer(const nlohmann::json& v) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<long long>::max())) return std::nullopt;
    return static_cast<long long>(u);
  }
  if (v.is_number_integer()) return v.get<long long>();
  if (v.is_number_float()) {
    const double d = v.get<double>();
    // 2^63 and above do not fit; below that every integral double converts exactly
    if (std::isfinite(d) && d == std::floor(d) && std::abs(d) < 9.2e18) return static_cast<long long>(d);
  }
  return std::nullopt;
}

long long Config::integer(const std::string& key) const {
  const auto& v = raw(key);
  if (const auto n = json_integer(v)) return *n;
  if (v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() == std::floor(v.get<double>()))
    fail(key, std::string(v.get<double>() > 0 ? "is too large" : "is too small") + " (got " + type_name(v) +
                  "; an integer here lies within +-" + std::to_string(std::numeric_limits<long long>::max()) + ")");
  fail(key, "must be an integer (got " + type_name(v) + ")");
}

long long Config::integer_or(const std::string& key, long long fallback) const {
  return has(key) ? integer(key) : fallback;
}

long long Config::integer_at_least(const std::string& key, long long min,
                                   long long fallback) const {
  return integer_in(key, min, std::numeric_limits<long long>::max(), fallback);
}

long long Config::integer_in(const std::string& key, long long min, long long max,
                             long long fallback) const {
  if (!has(key)) return fallback;
  const long long v = integer(key);
  if (v < min) fail(key, "must be >= " + std::to_string(min) + " (got " + std::to_string(v) + ")");
  if (v > max) fail(key, "must be at most " + std::to_string(max) + " (got " + std::to_string(v) + ")");
  return v;
}

int Config::int_at_least(const std::string& key, int min, int fallback) const {
  return static_cast<int>(integer_in(key, min, std::numeric_limits<int>::max(), fallback));
}

bool Config::boolean_or(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  const auto& v = raw(key);
  if (!v.is_boolean()) fail(key, "must be true or false (got " + type_name(v) + ")");
  return v.get<bool>();
}

std::string Config::string(const std::string& key) const {
  const auto& v = raw(key);
  if (!v.is_string()) fail(key, "must be a string (got " + type_name(v) + ")");
  return v.get<std::string>();
}

std::string Config::string_or(const std::string& key, const std::string& fallback) const {
  return has(key) ? string(key) : fallback;
}

std::vector<std::string> Config::string_list(const std::string& key) const {
  const auto& v = raw(key);
  if (v.is_string()) return {v.get<std::string>()};
  if (!v.is_array() || v.empty()) fail(key, "must be a string or a non-empty list of strings");
  std::vector<std::string> out;
  for (const auto& e : v) {
    if (!e.is_string()) fail(key, "must contain only strings (got " + type_name(e) + ")");
    out.push_back(e.get<std::string>());
  }
  return out;
}

std::string Config::path(const std::string& key) const {
  std::string p = string(key);
  check_path_text(p, where(key));
  return p;
}

std::string Config::path_or(const std::string& key, const std::string& fallback) const {
  return has(key) ? path(key) : fallback;
}

std::vector<std::string> Config::path_list(const std::string& key) const {
  std::vector<std::string> paths = string_list(key);
  for (const auto& p : paths) check_path_text(p, where(key));
  return expand_file_globs(paths, where(key));
}

Config Config::object(const std::string& key, const std::vector<std::string>& allowed) const {
  const auto& v = raw(key);
  if (!v.is_object()) fail(key, "must be an object (got " + type_name(v) + ")");
  Config c(v, file_, path_.empty() ? key : path_ + "." + key);
  if (!allowed.empty()) c.check_keys(allowed);
  return c;
}

void Config::check_keys(const std::vector<std::string>& allowed) const {
  for (auto it = value_.begin(); it != value_.end(); ++it)
    if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
      throw Error(file_ + ": unknown key '" + (path_.empty() ? "" : path_ + ".") + it.key() +
                  "'" + suggestion(it.key(), allowed));
}


}  // namespace vehs::tools
