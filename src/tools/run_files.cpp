#include "tools/run_files.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tools/file_globs.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/path_text.hpp"

namespace vehs::tools {

namespace {

namespace fs = std::filesystem;

bool is_output_file_key(const std::string& key) {
  static const char* const keys[] = {"output", "summary", "density", "sweep_table", "history", "px", "py", "pxy", "refit"};
  return std::find(std::begin(keys), std::end(keys), key) != std::end(keys);
}

// keys whose string values name input files in every tool (the model may also be inline)
bool is_input_file_key(const std::string& key) {
  static const char* const keys[] = {"data", "model", "learned", "truth", "reported", "monte_carlo", "path", "measurement"};
  return std::find(std::begin(keys), std::end(keys), key) != std::end(keys);
}

bool is_output_folder_key(const std::string& key) { return key == "figures" || key == "report"; }

// keys whose string values are paths (checked for control characters before any use)
bool is_path_key(const std::string& key) {
  return is_output_file_key(key) || is_input_file_key(key) || is_output_folder_key(key) || key == "fpk" ||
         key == "series";
}

struct Walk {
  const Config& config;
  OutputTransaction& transaction;
  std::vector<std::pair<std::string, std::string>> output_files;  // (key path, path)

  void check_folder(const std::string& where, const std::string& path) const {
    struct stat st {};
    if (path.empty()) throw Error(config.file() + ": '" + where + "' is empty");
    if (::stat(path.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
      throw Error(config.file() + ": '" + where + "' must be a folder, but " + path + " is a file");
    recover_stale_outputs(path);  // before the run reads or writes anything there
  }

  /// An output that would overwrite the config itself (a name copied with the config's): say
  /// which key to change. Sharing only the config's stem or folder is fine.
  void not_the_config(const std::string& where, const std::string& path) const {
    struct stat out {}, cfg {};  // the config exists: an output that does not is another file
    if (path.empty() || ::stat(path.c_str(), &out) != 0 || ::stat(config.file().c_str(), &cfg) != 0) return;
    if (out.st_dev != cfg.st_dev || out.st_ino != cfg.st_ino) return;
    const fs::path p(path);
    const std::string suggestion = (p.parent_path() / (p.stem().string() + "_out" + p.extension().string())).string();
    throw Error(config.file() + ": '" + where + "' names this config file itself, which the run would overwrite; "
                "change '" + where + "' to another file (e.g. \"" + suggestion + "\")");
  }

  void output(const std::string& where, const std::string& path) {
    not_the_config(where, path);
    try {
      transaction.check_output(path);
    } catch (const Error& e) {
      throw Error(config.file() + ": '" + where + "': " + e.what());
    }
    const std::string canonical = fs::weakly_canonical(fs::absolute(path)).string();
    for (const auto& [other_key, other] : output_files)
      if (fs::weakly_canonical(fs::absolute(other)).string() == canonical)
        throw Error(config.file() + ": '" + where + "' and '" + other_key + "' name the same file " + path +
                    " (give the outputs different names)");
    output_files.emplace_back(where, path);
  }

  static bool has_patterns(const nlohmann::json& v) {
    if (v.is_string()) return has_glob_characters(v.get<std::string>());
    return v.is_array() && std::any_of(v.begin(), v.end(), [](const nlohmann::json& e) { return has_patterns(e); });
  }

  // `data` with its glob patterns replaced by the files they match (as Config::path_list reads it)
  nlohmann::json expanded(const std::string& where, const nlohmann::json& v) const {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& e : v.is_array() ? v : nlohmann::json::array({v})) {
      if (!e.is_string()) {
        out.push_back(e);
        continue;
      }
      check_path_text(e.get<std::string>(), config.file() + ": '" + where + "'");
      for (const std::string& p : expand_file_glob(e.get<std::string>(), config.file() + ": '" + where + "'")) out.push_back(p);
    }
    return out;
  }

  // Strings of one list naming the same file (by st_dev/st_ino: also through links and "./").
  void distinct(const std::string& where, const nlohmann::json& list) const {
    std::vector<std::pair<std::pair<dev_t, ino_t>, std::string>> seen;
    for (const auto& e : list) {
      struct stat st {};
      if (!e.is_string() || ::stat(e.get<std::string>().c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
      const auto id = std::make_pair(st.st_dev, st.st_ino);
      for (const auto& [other, name] : seen)
        if (other == id)
          throw Error(config.file() + ": '" + where + "' lists the same file twice (" + name + " and " +
                      e.get<std::string>() + "); its samples would count twice");
      seen.emplace_back(id, e.get<std::string>());
    }
  }

  void value(const std::string& where, const std::string& key, const nlohmann::json& v) {
    if (key == "data" && has_patterns(v)) return value(where, key, expanded(where, v));
    if (v.is_string() && is_path_key(key)) check_path_text(v.get<std::string>(), config.file() + ": '" + where + "'");
    if (v.is_string() && is_output_file_key(key)) return output(where, v.get<std::string>());
    if (v.is_string() && is_output_folder_key(key)) return check_folder(where, v.get<std::string>());
    if (v.is_string() && is_input_file_key(key)) {  // a named input must exist: say which key names it
      struct stat st {};
      const std::string path = v.get<std::string>();
      if (path.empty() || ::stat(path.c_str(), &st) != 0)
        throw Error(config.file() + ": '" + where + "': " + (path.empty() ? "an empty path" : path + ": no such file"));
      if (S_ISDIR(st.st_mode)) throw Error(config.file() + ": '" + where + "': " + path + " is a directory, not a file");
      if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode))  // /dev/zero would be read for ever (a pipe: its reader decides)
        throw Error(config.file() + ": '" + where + "': " + path + " is a device, not a file");
    }
    if (v.is_string()) return transaction.protect(v.get<std::string>(), "input '" + where + "'");
    if (v.is_array()) {
      distinct(where, v);
      for (const auto& e : v) value(where, key, e);
    } else if (v.is_object()) {
      for (auto it = v.begin(); it != v.end(); ++it) value(where + "." + it.key(), it.key(), it.value());
    }
  }
};

}  // namespace

void declare_run_files(const Config& config, OutputTransaction& transaction) {
  transaction.protect(config.file(), "config file");
  Walk walk{config, transaction, {}};
  const auto& j = config.json();
  for (auto it = j.begin(); it != j.end(); ++it) walk.value(it.key(), it.key(), it.value());
}

}  // namespace vehs::tools
