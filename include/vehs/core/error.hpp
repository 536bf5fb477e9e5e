#pragma once
#include <stdexcept>
#include <string>

namespace vehs {

/// Every failure the user can cause (bad config, bad data, a model that cannot be solved)
/// is reported as a vehs::Error whose what() is a single line naming the file, field or row.
/// Executables print it as "<tool>: error: <what>" and exit with status 1.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Throws vehs::Error(message) when `condition` is false.
inline void require(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

}  // namespace vehs
