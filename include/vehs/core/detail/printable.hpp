#pragma once
// Bytes from files in messages: control bytes (NUL, CR, LF, ESC, ...) written as escapes, so that
// a message stays one line and is never cut at a NUL when printed through what(). UTF-8 and all
// other bytes are kept as they are.
#include <string>
#include <string_view>

namespace vehs::detail {

inline std::string printable(std::string_view s) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(s.size());
  for (const char ch : s) {
    const auto b = static_cast<unsigned char>(ch);
    if (b >= 0x20 && b != 0x7f) {
      out += ch;
    } else if (ch == '\n' || ch == '\r' || ch == '\t') {
      out += ch == '\n' ? "\\n" : ch == '\r' ? "\\r" : "\\t";
    } else {
      out += "\\x";
      out += kHex[b >> 4];
      out += kHex[b & 0xf];
    }
  }
  return out;
}

}  // namespace vehs::detail
