#pragma once
// Cell-centred grids of the stationary FPK (conventions.hpp): n cells over [min, max] per axis.
#include <cstddef>
#include <string>

namespace vehs::fpk {

/// One axis of a cell-centred grid: n cells over [min, max].
struct Axis {
  double min = -1.0, max = 1.0;
  int n = 100;
  double h() const { return (max - min) / n; }
  double center(int i) const { return min + (i + 0.5) * h(); }
  double face(int i) const { return min + i * h(); }  ///< i = 0..n
};

struct Grid {
  Axis x, y;
  std::size_t size() const { return static_cast<std::size_t>(x.n) * static_cast<std::size_t>(y.n); }
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(i) * static_cast<std::size_t>(y.n) + static_cast<std::size_t>(j);
  }
  double cell_area() const { return x.h() * y.h(); }
  /// Empty when valid (finite, min < max, n >= 3), else a one-line reason.
  std::string invalid_reason() const;
};

/// Which axes of a grid are chosen automatically.
struct GridRequest {
  bool auto_x = true, auto_y = true;
  Grid grid;  ///< fixed axes as given; for automatic axes only n is used
};

}  // namespace vehs::fpk
