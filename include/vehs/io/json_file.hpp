#pragma once
// Reading a JSON file (model files, configs, statistics) with one-line errors naming the file.
#include <string>

#include <nlohmann/json.hpp>

namespace vehs {

/// The JSON value in `path`. Throws vehs::Error "<path>: cannot open <what>" or
/// "<path>: not valid JSON (<parser message>)".
nlohmann::json read_json_file(const std::string& path, const std::string& what);

}  // namespace vehs
