#include "vehs/io/json_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/io/output_transaction.hpp"
#include "vehs/io/path_text.hpp"

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

/// The longest prefix of `s` of at most `n` bytes that ends on a UTF-8 character boundary (a cut
/// inside a character is invalid UTF-8, which nlohmann's dump refuses with an exception).
std::string utf8_prefix(const std::string& s, std::size_t n) {
  if (n >= s.size()) return s;
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;  // s[n]: a continuation byte
  return s.substr(0, n);
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
  std::string s = v.is_string() ? nlohmann::json(utf8_prefix(v.get<std::string>(), max_chars)).dump() : v.dump();
  out += s;
}

}  // namespace

std::string json_excerpt(const nlohmann::json& v, std::size_t max_chars) {
  std::string out;
  append_excerpt(v, out, max_chars);
  if (out.size() > max_chars + 3) out = utf8_prefix(out, max_chars) + "...";
  return out;
}

void check_json_text(const std::string& text, const std::string& where) {
  if (const std::string problem = structural_problem(text); !problem.empty()) throw Error(where + ": " + problem);
}

nlohmann::json parse_json_text(const std::string& text, const std::string& where) {
  check_json_text(text, where);
  // a key given twice in one object is an error (nlohmann keeps the last silently: a hand-edited
  // model with "x" twice, a config with two "output"s); the path names where
  std::vector<std::set<std::string>> keys;
  std::vector<std::string> path;
  const nlohmann::json::parser_callback_t no_duplicates = [&](int, nlohmann::json::parse_event_t event,
                                                              nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if (event == E::object_start) keys.emplace_back(), path.emplace_back();
    if (event == E::object_end && !keys.empty()) keys.pop_back(), path.pop_back();
    if (event == E::key && !keys.empty()) {
      const std::string k = parsed.get<std::string>();
      if (!keys.back().insert(k).second) {
        std::string at;
        for (std::size_t i = 0; i + 1 < path.size(); ++i)
          if (!path[i].empty()) at += (at.empty() ? "" : ".") + path[i];
        throw Error(where + ": key \"" + k + "\" appears twice in " + (at.empty() ? "the top-level object" : "'" + at + "'") +
                    " (each key may appear once)");
      }
      path.back() = k;
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, no_duplicates);  // strict: anything but whitespace after the value is an error
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for a number like 1e400
    const std::string message = e.what();  // "[json.exception.parse_error.101] parse error at line 3, ..."
    const std::size_t bracket = message.find("] ");
    throw Error(where + ": not valid JSON (" + (bracket == std::string::npos ? message : message.substr(bracket + 2)) +
                ")");
  }
}

std::string read_text_file(const std::string& path, const std::string& what) {
  check_path_text(path, what);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  if (S_ISDIR(st.st_mode)) throw Error(path + ": is a directory, not a " + what);
  // O_NONBLOCK: opening a pipe that has no writer returns at once (then reads end-of-file)
  // instead of waiting for ever; reads block again afterwards (process substitution works)
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw Error(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string text;
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw Error(path + ": cannot read " + what + " (" + why + ")");
    }
    if (n == 0) break;
    text.append(buf, static_cast<std::size_t>(n));
    if (text.size() > kMaxJsonBytes) {  // /dev/zero and friends: never a config
      ::close(fd);
      throw Error(path + ": larger than " + std::to_string(kMaxJsonBytes >> 20) + " MB, not a " + what);
    }
  }
  ::close(fd);
  return text;
}

nlohmann::json read_json_file(const std::string& path, const std::string& what) {
  std::string text = read_text_file(path, what);
  if (OutputTransaction* t = OutputTransaction::active()) t->protect(path, what);  // never an output of this run
  return parse_json_text(text, path);
}

}  // namespace vehs
