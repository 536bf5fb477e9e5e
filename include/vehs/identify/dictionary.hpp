#pragma once
// A dictionary of regression terms compiled for fast evaluation on blocks of samples.
//
// The identification regresses a target (an acceleration estimate, or a squared residual) on
// the values of the terms of docs/model-file.md at states (x, v, u): x the displacement, v a
// velocity estimate, u a recorded drive. Besides values, the corrected estimators need
// derivatives with respect to v (Itô correction of velocity-dependent terms, errors-in-variables
// correction of sensor noise) and x (sensor-noise correction of the displacement).
//
// Evaluation works on blocks of up to kBlockRows rows held column-wise (RowBlock); outputs are
// column-major blocks with one column per term (leading dimension `ld`), so that Gram matrices
// are accumulated by rank-k updates and the inner loops vectorise.
//
// Extension point: terms are per-sample functions of (x, v, u). Regressors that need a whole
// record (a filtered velocity, cos/sin of ωt, a profile over a nonlinear parameter) will be added
// as further columns filled per record span before the per-block accumulation; the accumulators
// in identify.cpp only see feature blocks.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/terms.hpp"
#include "vehs/identify/smoothed_sign.hpp"

namespace vehs::identify {

inline constexpr int kBlockRows = 256;
/// Highest power of x or v a term may have (Term::parse accepts up to 64).
inline constexpr int kMaxPow = 64;

/// Up to kBlockRows regression rows: displacement, velocity estimate, acceleration estimate
/// (the drift target) and drive.
struct RowBlock {
  int m = 0;
  alignas(64) double x[kBlockRows];
  alignas(64) double v[kBlockRows];
  alignas(64) double a[kBlockRows];
  alignas(64) double u[kBlockRows];
};

class Dictionary {
 public:
  Dictionary() = default;
  explicit Dictionary(std::vector<Term> terms) : terms_(std::move(terms)) {
    for (const auto& t : terms_) {
      if (t.kind == TermKind::Monomial) {
        max_px_ = std::max(max_px_, t.px);
        max_py_ = std::max(max_py_, t.py);
      }
      if (t.depends_on_u()) uses_u_ = true;
    }
    for (std::size_t k = 0; k < terms_.size(); ++k)
      if (terms_[k].depends_on_y()) velocity_terms_.push_back(static_cast<int>(k));
    // evaluation plan: pure powers of x in increasing order, each from the previous one
    pure_x_.assign(static_cast<std::size_t>(max_px_ + 1), -1);
    for (std::size_t k = 0; k < terms_.size(); ++k)
      if (terms_[k].kind == TermKind::Monomial && terms_[k].py == 0)
        pure_x_[static_cast<std::size_t>(terms_[k].px)] = static_cast<int>(k);
  }

  /// The dictionary of the terms `indices` (in that order), with the same sign-kernel width.
  Dictionary subset(const std::vector<int>& indices) const {
    std::vector<Term> t;
    for (int i : indices) t.push_back(terms_[static_cast<std::size_t>(i)]);
    Dictionary d(std::move(t));
    d.sign_h_ = sign_h_;
    d.smooth_ = smooth_;
    return d;
  }

  int size() const { return static_cast<int>(terms_.size()); }
  const std::vector<Term>& terms() const { return terms_; }
  const Term& term(int k) const { return terms_[static_cast<std::size_t>(k)]; }
  std::string name(int k) const { return term(k).name(); }
  bool uses_u() const { return uses_u_; }
  bool depends_on_v() const { return !velocity_terms_.empty(); }
  /// Indices of the terms that depend on v (the only ones with non-zero v-derivatives).
  const std::vector<int>& velocity_terms() const { return velocity_terms_; }
  /// Half-width h of the box kernel standing in for δ(v) in ∂sign(v)/∂v = 2δ(v): the
  /// derivative is taken as 1{|v| < h}/h. Set from the spread of the velocity estimates.
  void set_sign_kernel_halfwidth(double h) { sign_h_ = h; }
  double sign_kernel_halfwidth() const { return sign_h_; }
  /// Central kinematics at h = kΔt: the sign(y) column becomes the smoothed sign S(v̂) of
  /// smoothed_sign.hpp (what the tent-averaged acceleration sees of friction), with a22 from
  /// `a22` (a pilot diffusion fit, floored at `floor`) and v̂ noise variance `noise_var`; its
  /// v-derivatives are S' and S'' (no box kernel).
  void set_sign_smoothing(double h, TermList a22, double floor, double noise_var) {
    smooth_.on = true;
    smooth_.h = h;
    smooth_.a22 = std::move(a22);
    smooth_.floor = floor;
    smooth_.d = 2.0 * noise_var;
  }

  /// Scratch doubles the block methods need.
  std::size_t scratch_size() const {
    return static_cast<std::size_t>(max_px_ + 1 + max_py_ + 1) * kBlockRows;
  }

  /// Term values: out[k·ld + i] = term_k(x_i, v_i, u_i), i < b.m.
  void values(const RowBlock& b, double* out, std::ptrdiff_t ld, double* scratch) const {
    const int m = b.m;
    double* xp = scratch;                                   // (max_px+1) columns
    double* vp = scratch + (max_px_ + 1) * kBlockRows;      // (max_py+1) columns
    // powers of x: straight into the output column of a pure power when there is one
    const double* xcol[kMaxPow + 1];
    const double* prev = nullptr;
    for (int p = 0; p <= max_px_; ++p) {
      const int k = pure_x_[static_cast<std::size_t>(p)];
      double* dst = k >= 0 ? out + static_cast<std::ptrdiff_t>(k) * ld : xp + p * kBlockRows;
      if (p == 0)
        for (int i = 0; i < m; ++i) dst[i] = 1.0;
      else if (p == 1)
        for (int i = 0; i < m; ++i) dst[i] = b.x[i];
      else
        for (int i = 0; i < m; ++i) dst[i] = prev[i] * b.x[i];
      xcol[p] = dst;
      prev = dst;
    }
    if (max_py_ >= 2) powers(b.v, m, max_py_, vp);
    for (std::size_t k = 0; k < terms_.size(); ++k) {
      const Term& t = terms_[k];
      double* o = out + static_cast<std::ptrdiff_t>(k) * ld;
      switch (t.kind) {
        case TermKind::Monomial: {
          if (t.py == 0) break;  // written above
          const double* px = xcol[t.px];
          const double* py = t.py == 1 ? b.v : vp + t.py * kBlockRows;
          if (t.px == 0)
            for (int i = 0; i < m; ++i) o[i] = py[i];
          else
            for (int i = 0; i < m; ++i) o[i] = px[i] * py[i];
          break;
        }
        case TermKind::SignY:
          if (smooth_.on)
            for (int i = 0; i < m; ++i) o[i] = smooth_.at(b.x[i], b.v[i]).value;
          else
            for (int i = 0; i < m; ++i) o[i] = static_cast<double>((b.v[i] > 0) - (b.v[i] < 0));
          break;
        case TermKind::YAbsY:
          for (int i = 0; i < m; ++i) o[i] = b.v[i] * std::abs(b.v[i]);
          break;
        case TermKind::Drive:
          for (int i = 0; i < m; ++i) o[i] = b.u[i];
          break;
        case TermKind::User:
          for (int i = 0; i < m; ++i) o[i] = (*t.fn)(b.x[i], b.v[i], b.u[i]);
          break;
      }
    }
  }

  /// ∂/∂v of the velocity terms: out[j·ld + i] for j over velocity_terms().
  void d_dv(const RowBlock& b, double* out, std::ptrdiff_t ld, double* scratch) const {
    const int m = b.m;
    double* xp = scratch;
    double* vp = scratch + (max_px_ + 1) * kBlockRows;
    powers(b.x, m, max_px_, xp);
    powers(b.v, m, max_py_, vp);
    for (std::size_t j = 0; j < velocity_terms_.size(); ++j) {
      const Term& t = terms_[static_cast<std::size_t>(velocity_terms_[j])];
      double* o = out + static_cast<std::ptrdiff_t>(j) * ld;
      switch (t.kind) {
        case TermKind::Monomial: {
          const double* px = xp + t.px * kBlockRows;
          const double* py = vp + (t.py - 1) * kBlockRows;
          const double c = t.py;
          for (int i = 0; i < m; ++i) o[i] = c * px[i] * py[i];
          break;
        }
        case TermKind::SignY: {
          if (smooth_.on) {
            for (int i = 0; i < m; ++i) o[i] = smooth_.at(b.x[i], b.v[i]).d1;
            break;
          }
          const double h = sign_h_, inv = 1.0 / sign_h_;
          for (int i = 0; i < m; ++i) o[i] = std::abs(b.v[i]) < h ? inv : 0.0;
          break;
        }
        case TermKind::YAbsY:
          for (int i = 0; i < m; ++i) o[i] = 2.0 * std::abs(b.v[i]);
          break;
        case TermKind::Drive:
          for (int i = 0; i < m; ++i) o[i] = 0.0;
          break;
        case TermKind::User: {  // central difference over the sign kernel's width: a jump
          const double h = sign_h_, inv = 0.5 / sign_h_;  // shows as sign(y)'s box kernel does
          const auto& g = *t.fn;
          for (int i = 0; i < m; ++i) o[i] = (g(b.x[i], b.v[i] + h, b.u[i]) - g(b.x[i], b.v[i] - h, b.u[i])) * inv;
          break;
        }
      }
    }
  }

  /// The friction's response term of the Itô correction (smoothed_sign.hpp): per velocity term j,
  /// ½a22·S'(v)·q₀√(h/a22) for a smoothed sign(y), else 0: out[j·ld + i].
  void sign_ito_response(const RowBlock& b, double* out, std::ptrdiff_t ld) const {
    for (std::size_t j = 0; j < velocity_terms_.size(); ++j) {
      const Term& t = terms_[static_cast<std::size_t>(velocity_terms_[j])];
      double* o = out + static_cast<std::ptrdiff_t>(j) * ld;
      for (int i = 0; i < b.m; ++i) o[i] = 0.0;
      if (t.kind != TermKind::SignY || !smooth_.on) continue;
      for (int i = 0; i < b.m; ++i) {
        const double a22 = std::max(evaluate(smooth_.a22, b.x[i], b.v[i]), smooth_.floor);
        o[i] = 0.5 * kSignResponse * std::sqrt(a22 * smooth_.h) * smooth_.at(b.x[i], b.v[i]).d1;
      }
    }
  }
  bool sign_smoothing() const { return smooth_.on; }

  /// ∂²/∂v² of the velocity terms (0 for an unsmoothed sign(v)): out[j·ld + i].
  void d2_dv2(const RowBlock& b, double* out, std::ptrdiff_t ld, double* scratch) const {
    const int m = b.m;
    double* xp = scratch;
    double* vp = scratch + (max_px_ + 1) * kBlockRows;
    powers(b.x, m, max_px_, xp);
    powers(b.v, m, max_py_, vp);
    for (std::size_t j = 0; j < velocity_terms_.size(); ++j) {
      const Term& t = terms_[static_cast<std::size_t>(velocity_terms_[j])];
      double* o = out + static_cast<std::ptrdiff_t>(j) * ld;
      if (t.kind == TermKind::Monomial && t.py >= 2) {
        const double* px = xp + t.px * kBlockRows;
        const double* py = vp + (t.py - 2) * kBlockRows;
        const double c = t.py * (t.py - 1);
        for (int i = 0; i < m; ++i) o[i] = c * px[i] * py[i];
      } else if (t.kind == TermKind::YAbsY) {
        for (int i = 0; i < m; ++i) o[i] = 2.0 * static_cast<double>((b.v[i] > 0) - (b.v[i] < 0));
      } else if (t.kind == TermKind::SignY && smooth_.on) {
        for (int i = 0; i < m; ++i) o[i] = smooth_.at(b.x[i], b.v[i]).d2;
      } else if (t.kind == TermKind::User) {
        const double h = sign_h_, inv = 1.0 / (sign_h_ * sign_h_);
        const auto& g = *t.fn;
        for (int i = 0; i < m; ++i)
          o[i] = (g(b.x[i], b.v[i] + h, b.u[i]) - 2.0 * g(b.x[i], b.v[i], b.u[i]) + g(b.x[i], b.v[i] - h, b.u[i])) * inv;
      } else {
        for (int i = 0; i < m; ++i) o[i] = 0.0;
      }
    }
  }

  /// ∂/∂x of all terms: out[k·ld + i].
  void d_dx(const RowBlock& b, double* out, std::ptrdiff_t ld, double* scratch) const {
    const int m = b.m;
    double* xp = scratch;
    double* vp = scratch + (max_px_ + 1) * kBlockRows;
    powers(b.x, m, max_px_, xp);
    powers(b.v, m, max_py_, vp);
    for (std::size_t k = 0; k < terms_.size(); ++k) {
      const Term& t = terms_[k];
      double* o = out + static_cast<std::ptrdiff_t>(k) * ld;
      if (t.kind == TermKind::Monomial && t.px >= 1) {
        const double* px = xp + (t.px - 1) * kBlockRows;
        const double* py = vp + t.py * kBlockRows;
        const double c = t.px;
        for (int i = 0; i < m; ++i) o[i] = c * px[i] * py[i];
      } else if (t.kind == TermKind::User) {
        for (int i = 0; i < m; ++i) o[i] = t.d_dx(b.x[i], b.v[i], b.u[i]);
      } else {
        for (int i = 0; i < m; ++i) o[i] = 0.0;
      }
    }
  }

 private:
  static void powers(const double* z, int m, int n, double* p) {
    for (int i = 0; i < m; ++i) p[i] = 1.0;
    for (int j = 1; j <= n; ++j) {
      const double* prev = p + (j - 1) * kBlockRows;
      double* cur = p + j * kBlockRows;
      for (int i = 0; i < m; ++i) cur[i] = prev[i] * z[i];
    }
  }

  std::vector<Term> terms_;
  std::vector<int> velocity_terms_;
  std::vector<int> pure_x_;  // index of the term x^p (py = 0), or -1
  int max_px_ = 0, max_py_ = 0;
  bool uses_u_ = false;
  double sign_h_ = 1e-3;
  struct SignSmoothing {
    bool on = false;
    double h = 0.0, floor = 0.0, d = 0.0;
    TermList a22;
    SmoothedSign at(double x, double v) const {
      return smoothed_sign(v, std::max(evaluate(a22, x, v), floor) * h, d);
    }
  } smooth_;
};

}  // namespace vehs::identify
