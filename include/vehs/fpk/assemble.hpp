#pragma once
// The sparse finite-difference operator of the stationary FPK equation (stationary.hpp describes
// the schemes), as a header kernel over any provider of the coefficients — FpkModel, or a
// user's own b2 and a22: anything with
//     double b2(x, y), db2_dy(x, y), a22(x, y), da22_dy(x, y), d2a22_dy2(x, y) const;
//     bool has_sign_y() const;   std::string where() const;   (the name used in errors)
// The operator is assembled directly into compressed-column storage with a fixed pattern (5
// points, 7 for the fourth-order flux), so that all models on one grid share one pattern (and
// one symbolic factorisation).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "vehs/core/enum_names.hpp"
#include "vehs/core/error.hpp"
#include "vehs/fpk/grid.hpp"

namespace vehs::fpk {

enum class Scheme { Flux, Flux2, Central, PaperLiteral };
inline constexpr EnumNames<Scheme, 4> kSchemeNames{{{Scheme::Flux, "flux"},
                                                    {Scheme::Flux2, "flux2"},
                                                    {Scheme::Central, "central"},
                                                    {Scheme::PaperLiteral, "paper_literal"}}};

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

namespace detail {

/// Slot positions of the pattern in compressed-column storage; column k = i·ny + j holds rows
/// in the order W2 (k − 2ny, wide only), W (k − ny), S (k − 1), C (k), N (k + 1), E (k + ny),
/// E2 (k + 2ny, wide only). `wide` adds the second x-neighbours of the fourth-order x-flux.
struct Pattern {
  int nx, ny;
  bool wide;
  std::vector<int> start;  // column starts (size n + 1)

  Pattern(int nx_, int ny_, bool wide_)
      : nx(nx_), ny(ny_), wide(wide_), start(static_cast<std::size_t>(nx_) * ny_ + 1) {
    int pos = 0;
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) {
        start[static_cast<std::size_t>(i) * ny + j] = pos;
        pos += 1 + (i > 0) + (j > 0) + (j < ny - 1) + (i < nx - 1) + (wide && i > 1) + (wide && i < nx - 2);
      }
    start.back() = pos;
  }
  int col(int i, int j) const { return i * ny + j; }
  int W2(int i, int j) const { return start[col(i, j)]; }
  int W(int i, int j) const { return start[col(i, j)] + (wide && i > 1); }
  int S(int i, int j) const { return W(i, j) + (i > 0); }
  int C(int i, int j) const { return S(i, j) + (j > 0); }
  int N(int i, int j) const { return C(i, j) + 1; }
  int E(int i, int j) const { return C(i, j) + 1 + (j < ny - 1); }
  int E2(int i, int j) const { return E(i, j) + 1; }
  /// Slot of row (i + di, j) in column (i, j), di in −2..2 (must exist).
  int X(int i, int j, int di) const {
    switch (di) {
      case -2: return W2(i, j);
      case -1: return W(i, j);
      case 0: return C(i, j);
      case 1: return E(i, j);
      default: return E2(i, j);
    }
  }
};

inline std::string point(double x, double y) {
  std::ostringstream os;
  os.precision(6);
  os << "(x, y) = (" << x << ", " << y << ")";
  return os.str();
}

}  // namespace detail

/// The stationary FPK operator A (A p = 0) of `model` on `grid`. Throws vehs::Error when a
/// coefficient is not finite on the grid or a22 is negative somewhere (naming the point), or for
/// sign(y) with a non-conservative scheme.
template <class Coefficients>
SparseMatrix assemble_operator(const Coefficients& model, const Grid& grid, Scheme scheme) {
  using detail::Pattern;
  using detail::point;
  if (auto why = grid.invalid_reason(); !why.empty()) throw Error(why);
  if (scheme != Scheme::Flux && scheme != Scheme::Flux2 && model.has_sign_y())
    throw Error(model.where() + ": the drift term sign(y) has a delta-function y-derivative that "
                                "the expanded central scheme cannot represent; use scheme 'flux'");
  const int nx = grid.x.n, ny = grid.y.n;
  const int n = nx * ny;
  const bool wide = scheme == Scheme::Flux && nx >= 4;
  const Pattern pat(nx, ny, wide);
  SparseMatrix A(n, n);
  const int nnz = pat.start.back();
  A.resizeNonZeros(nnz);
  int* outer = A.outerIndexPtr();
  int* inner = A.innerIndexPtr();
  double* val = A.valuePtr();
  for (int k = 0; k <= n; ++k) outer[k] = pat.start[static_cast<std::size_t>(k)];
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const int k = pat.col(i, j);
      int p = pat.start[static_cast<std::size_t>(k)];
      if (wide && i > 1) inner[p++] = k - 2 * ny;
      if (i > 0) inner[p++] = k - ny;
      if (j > 0) inner[p++] = k - 1;
      inner[p++] = k;
      if (j < ny - 1) inner[p++] = k + 1;
      if (i < nx - 1) inner[p++] = k + ny;
      if (wide && i < nx - 2) inner[p++] = k + 2 * ny;
    }
  std::fill(val, val + nnz, 0.0);

  const double hx = grid.x.h(), hy = grid.y.h();
  auto check_a22 = [&](double a, double x, double y) {
    if (!std::isfinite(a))
      throw Error(model.where() + ": diffusion a22 is not finite at " + point(x, y));
    if (a < 0.0) {
      std::ostringstream os;
      os << model.where() << ": diffusion a22 = " << a << " is negative at " << point(x, y)
         << " (a variance rate must be >= 0 on the whole grid)";
      throw Error(os.str());
    }
  };
  auto check_b2 = [&](double b, double x, double y) {
    if (!std::isfinite(b)) throw Error(model.where() + ": drift b2 is not finite at " + point(x, y));
  };

  if (scheme == Scheme::Flux || scheme == Scheme::Flux2) {
    // x-faces: flux y_j·p_face from L = (i, j) to R = (i+1, j); p_face is the fourth-order
    // interpolation (−p_i−1 + 7p_i + 7p_i+1 − p_i+2)/12 where both second neighbours exist,
    // else the average (p_i + p_i+1)/2 (next to the outer faces, where p is negligible).
    // Row L gets −flux/hx, row R +flux/hx; the entry (row, column c) sits in column c.
    for (int i = 0; i + 1 < nx; ++i) {
      const bool fourth = wide && i >= 1 && i + 2 < nx;
      const int lo = fourth ? -1 : 0, hi = fourth ? 2 : 1;
      for (int j = 0; j < ny; ++j) {
        const double c = grid.y.center(j) / hx;
        for (int m = lo; m <= hi; ++m) {
          const double w = fourth ? ((m == 0 || m == 1) ? 7.0 / 12.0 : -1.0 / 12.0) : 0.5;
          const int ic = i + m;  // column cell (ic, j)
          val[pat.X(ic, j, i - ic)] -= w * c;      // row L = (i, j)
          val[pat.X(ic, j, i + 1 - ic)] += w * c;  // row R = (i+1, j)
        }
      }
    }
    // y-faces: flux b2(face)(p_L + p_R)/2 − (a22_R p_R − a22_L p_L)/(2 hy), L = (i, j), R = (i, j+1).
    std::vector<double> a_col(static_cast<std::size_t>(ny));
    for (int i = 0; i < nx; ++i) {
      const double x = grid.x.center(i);
      for (int j = 0; j < ny; ++j) {
        const double y = grid.y.center(j);
        a_col[static_cast<std::size_t>(j)] = model.a22(x, y);
        check_a22(a_col[static_cast<std::size_t>(j)], x, y);
      }
      for (int j = 0; j + 1 < ny; ++j) {
        const double yf = grid.y.face(j + 1);
        const double b = model.b2(x, yf);
        check_b2(b, x, yf);
        const double cl = (0.5 * b + 0.5 * a_col[static_cast<std::size_t>(j)] / hy) / hy;
        const double cr = (0.5 * b - 0.5 * a_col[static_cast<std::size_t>(j) + 1] / hy) / hy;
        // column L = (i, j): rows L (C) and R (N)
        val[pat.C(i, j)] -= cl;
        val[pat.N(i, j)] += cl;
        // column R = (i, j+1): rows L (S) and R (C)
        val[pat.S(i, j + 1)] -= cr;
        val[pat.C(i, j + 1)] += cr;
      }
    }
  } else {
    const double f = scheme == Scheme::PaperLiteral ? 2.0 : 1.0;  // the misprint: /h, not /2h
    for (int i = 0; i < nx; ++i) {
      const double x = grid.x.center(i);
      for (int j = 0; j < ny; ++j) {
        const double y = grid.y.center(j);
        const double b = model.b2(x, y), db = model.db2_dy(x, y);
        const double a = model.a22(x, y), da = model.da22_dy(x, y), dda = model.d2a22_dy2(x, y);
        check_b2(b, x, y);
        check_b2(db, x, y);
        check_a22(a, x, y);
        const double cx = f * y / (2.0 * hx);            // −y ∂x p
        const double g = f * (-b + da) / (2.0 * hy);     // (−b2 + ∂y a22) ∂y p
        const double d2 = 0.5 * a / (hy * hy);           // ½ a22 ∂²y p
        // row (i, j): the entry for neighbour column c sits in column c at the opposite slot.
        if (i > 0) val[pat.E(i - 1, j)] += cx;           // p_{i−1}: +y/(2hx)
        if (i < nx - 1) val[pat.W(i + 1, j)] -= cx;      // p_{i+1}: −y/(2hx)
        if (j > 0) val[pat.N(i, j - 1)] += d2 - g;
        if (j < ny - 1) val[pat.S(i, j + 1)] += d2 + g;
        val[pat.C(i, j)] += -db + 0.5 * dda - 2.0 * d2;
      }
    }
  }
  return A;
}

}  // namespace vehs::fpk
