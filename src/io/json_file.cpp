#include "vehs/io/json_file.hpp"

#include <fstream>

#include "vehs/core/error.hpp"

namespace vehs {

nlohmann::json read_json_file(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open " + what);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    const std::string message = e.what();  // "[json.exception.parse_error.101] parse error at line 3, ..."
    const std::size_t bracket = message.find("] ");
    throw Error(path + ": not valid JSON (" + (bracket == std::string::npos ? message : message.substr(bracket + 2)) +
                ")");
  }
}

}  // namespace vehs
