#include "vehs/fpk/grid.hpp"

#include <cmath>

namespace vehs::fpk {

std::string Grid::invalid_reason() const {
  for (const auto* a : {&x, &y}) {
    const char* name = a == &x ? "x" : "y";
    if (!std::isfinite(a->min) || !std::isfinite(a->max))
      return std::string("grid.") + name + ": bounds must be finite";
    if (!(a->min < a->max)) return std::string("grid.") + name + ": min must be < max";
    if (a->n < 3) return std::string("grid.") + name + ": needs at least 3 cells";
    if (a->n > 20000) return std::string("grid.") + name + ": more than 20000 cells per axis";
  }
  if (size() > 50'000'000ULL) return "grid: more than 5e7 cells";
  return "";
}

}  // namespace vehs::fpk
