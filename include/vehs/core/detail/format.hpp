#pragma once
// Numbers in messages: `digits` significant digits, the stream's shortest form (1e-05, 0.25).
#include <sstream>
#include <string>

namespace vehs::detail {

inline std::string format_number(double v, int digits) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

}  // namespace vehs::detail
