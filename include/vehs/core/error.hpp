#pragma once
#include <stdexcept>
#include <string>

#include "vehs/core/detail/printable.hpp"

namespace vehs {

/// Every failure the user can cause (bad config, bad data, a model that cannot be solved)
/// is reported as a vehs::Error whose what() is a single line naming the file, field or row.
/// Executables print it as "<tool>: error: <what>" and exit with status 1. Control bytes that
/// came from a file (a NUL or CR inside a field, a name) are kept visible as escapes (`\x00`, `\r`):
/// what() is a C string, which a raw NUL would cut short.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(detail::printable(message)) {}
};

/// Throws vehs::Error(message) when `condition` is false.
inline void require(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

}  // namespace vehs
