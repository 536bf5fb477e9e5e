#include "vehs/io/json_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "vehs/core/error.hpp"
#include "vehs/io/output_transaction.hpp"

namespace vehs {

namespace {

// What the parser must not see: nesting deeper than kMaxJsonDepth (its printing and copying
// recurse), or a NUL byte outside strings (nlohmann's lexer takes it for the end of the input and
// ignores the rest). Empty when the text has neither; else "<problem> (line L)".
std::string structural_problem(const std::string& text) {
  int depth = 0;
  bool in_string = false, escaped = false;
  std::size_t line = 1;
  for (const char c : text) {
    if (c == '\n') ++line;
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '\0') {
      return "not valid JSON (a NUL byte, line " + std::to_string(line) + ")";
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        return "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels (line " + std::to_string(line) + ")";
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return "";
}

void append_excerpt(const nlohmann::json& v, std::string& out, std::size_t max_chars) {
  if (out.size() >= max_chars) return;
  if (v.is_array() || v.is_object()) {
    out += v.is_array() ? '[' : '{';
    bool first = true;
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (out.size() >= max_chars) {
        out += "...";
        break;
      }
      if (!first) out += ", ";
      first = false;
      if (v.is_object()) out += nlohmann::json(it.key()).dump() + ": ";
      append_excerpt(*it, out, max_chars);
    }
    out += v.is_array() ? ']' : '}';
    return;
  }
  std::string s = v.is_string() ? nlohmann::json(v.get<std::string>().substr(0, max_chars)).dump() : v.dump();
  out += s;
}

}  // namespace

std::string json_excerpt(const nlohmann::json& v, std::size_t max_chars) {
  std::string out;
  append_excerpt(v, out, max_chars);
  if (out.size() > max_chars + 3) out = out.substr(0, max_chars) + "...";
  return out;
}

nlohmann::json parse_json_text(const std::string& text, const std::string& where) {
  if (const std::string problem = structural_problem(text); !problem.empty()) throw Error(where + ": " + problem);
  try {
    return nlohmann::json::parse(text);  // strict: anything but whitespace after the value is an error
  } catch (const nlohmann::json::parse_error& e) {
    const std::string message = e.what();  // "[json.exception.parse_error.101] parse error at line 3, ..."
    const std::size_t bracket = message.find("] ");
    throw Error(where + ": not valid JSON (" + (bracket == std::string::npos ? message : message.substr(bracket + 2)) +
                ")");
  }
}

nlohmann::json read_json_file(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  if (S_ISDIR(st.st_mode)) throw Error(path + ": is a directory, not a " + what);
  if (!S_ISREG(st.st_mode)) throw Error(path + ": is not a regular file (device, pipe or socket), not a " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(path + ": cannot read " + what);
  if (OutputTransaction* t = OutputTransaction::active()) t->protect(path, what);  // never an output of this run
  return parse_json_text(text.str(), path);
}

}  // namespace vehs
