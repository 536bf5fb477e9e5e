#pragma once
// JSON configs of the executables: one key table per tool is the single source for `--help`
// and for rejecting unknown keys; typed getters give one-line errors naming file and key.
// (Tools layer: not part of the library's public API.)
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace vehs::tools {

struct KeySpec {
  std::string name;
  std::string type;           ///< e.g. "number", "string", "object|path", "[a, b, n]"
  std::string help;           ///< one or more sentences
  std::string default_text;   ///< empty: required (unless `optional`)
  bool optional = false;      ///< optional without a default (feature switched off)
};

struct ConfigSchema {
  std::string tool;     ///< executable name
  std::string summary;  ///< what the tool does (first paragraph of --help)
  std::vector<KeySpec> keys;
  std::string epilog;   ///< extra help (examples, outputs)

  /// The full key table as printed by --help.
  std::string help_text() const;
  /// The same key table as Markdown (--help-markdown): the summary, a table of key, type,
  /// default and the first sentence of the help, then every key with its full help.
  std::string markdown_text() const;
  const KeySpec* find(const std::string& key) const;
};

/// `schema` with `keys` inserted after the key `after` (keys shared by several tools).
ConfigSchema with_keys_after(const std::string& after, const std::vector<KeySpec>& keys, ConfigSchema schema);

/// A view of one JSON object of a config file, remembering where it came from so that every
/// error names the file and the key path ("sim.json: 'grid.x' must be [min, max, n]").
/// The value of a JSON integer (or of a float with an integral value) when it fits a long long;
/// nullopt for anything else (2.5, 1e30, 2^64 - 1, a string).
std::optional<long long> json_integer(const nlohmann::json& v);

/// The keys a measurement file (`"measurement": "rig.json"`) may hold: the recordings of one rig
/// described once for every tool's config.
const std::vector<std::string>& measurement_file_keys();

/// Merges the measurement file that `j["measurement"]` names (when `schema` has that key) into the
/// config object `j`: each of its keys the config does not give itself. `file` names the config in
/// errors; an unknown key or a file that is not a JSON object is a one-line error naming the file.
void include_measurement_file(nlohmann::json& j, const std::string& file, const ConfigSchema& schema);

class Config {
 public:
  Config(nlohmann::json value, std::string file, std::string path = "");

  /// Reads and parses `file`; rejects keys not in `schema` (suggesting the closest name).
  static Config load(const std::string& file, const ConfigSchema& schema);
  /// Applies a "key=json" override (from --set) to the top-level object.
  void set_override(const std::string& assignment, const ConfigSchema& schema);

  bool has(const std::string& key) const;
  const nlohmann::json& raw(const std::string& key) const;  ///< throws when missing
  const nlohmann::json& json() const { return value_; }
  const std::string& file() const { return file_; }
  /// "file: 'path.key'" — the prefix used in error messages.
  std::string where(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  double number(const std::string& key) const;
  double number_or(const std::string& key, double fallback) const;
  double positive(const std::string& key) const;  ///< finite and > 0
  double positive_or(const std::string& key, double fallback) const;
  double non_negative_or(const std::string& key, double fallback) const;
  long long integer(const std::string& key) const;
  long long integer_or(const std::string& key, long long fallback) const;
  long long integer_at_least(const std::string& key, long long min, long long fallback) const;
  /// An integer in [min, max] (`fallback` when absent); values outside are refused, never
  /// narrowed ("must be at most max (got v)").
  long long integer_in(const std::string& key, long long min, long long max, long long fallback) const;
  /// An integer >= min that fits an int (a count or size narrowed to int by the caller's options).
  int int_at_least(const std::string& key, int min, int fallback) const;
  bool boolean_or(const std::string& key, bool fallback) const;
  std::string string(const std::string& key) const;
  std::string string_or(const std::string& key, const std::string& fallback) const;
  /// A string or list of strings as a list.
  std::vector<std::string> string_list(const std::string& key) const;
  /// string / string_or / string_list for a file or folder path: a control character in it
  /// (vehs/io/path_text.hpp: a NUL would cut it) is an error naming the key.
  std::string path(const std::string& key) const;
  std::string path_or(const std::string& key, const std::string& fallback) const;
  /// path_list also expands glob patterns (tools/file_globs.hpp): "run_*.csv" gives the matching files.
  std::vector<std::string> path_list(const std::string& key) const;
  /// A sub-object, rejecting keys outside `allowed` (empty: accept anything).
  Config object(const std::string& key, const std::vector<std::string>& allowed = {}) const;
  /// Checks that this object's keys are within `allowed`.
  void check_keys(const std::vector<std::string>& allowed) const;

 private:
  nlohmann::json value_;
  std::string file_;
  std::string path_;
};

}  // namespace vehs::tools
