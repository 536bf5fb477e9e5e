#include "vehs/io/path_text.hpp"

#include <cstdio>

#include "vehs/core/error.hpp"

namespace vehs {

namespace {
bool is_control(char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }
}  // namespace

std::string path_text_problem(const std::string& path) {
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (!is_control(path[i])) continue;
    char code[8];
    std::snprintf(code, sizeof code, "0x%02x", static_cast<unsigned>(static_cast<unsigned char>(path[i])));
    const char* name = path[i] == '\0' ? " (NUL)" : path[i] == '\n' ? " (line feed)" : path[i] == '\t' ? " (tab)" : "";
    return "the path '" + escaped_path(path) + "' contains the control character " + code + name + " at byte " +
           std::to_string(i + 1) + " (paths must not hold control characters)";
  }
  return "";
}

std::string escaped_path(const std::string& path) {
  std::string out;
  for (const char c : path) {
    if (!is_control(c)) {
      out += c;
      continue;
    }
    char code[8];
    std::snprintf(code, sizeof code, "\\x%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
    out += code;
  }
  return out;
}

void check_path_text(const std::string& path, const std::string& where) {
  if (const std::string why = path_text_problem(path); !why.empty()) throw Error(where + ": " + why);
}

}  // namespace vehs
