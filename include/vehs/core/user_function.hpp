#pragma once
// A term the catalogue lacks, written by the user as an expression in the state: "tanh(y/0.01)",
// "y*(y>0)", "u*x", "(x>0.8)*(x-0.8)". Parsed once by muParser (a comparison is 1 or 0, the usual
// functions sin, cos, tanh, exp, log, sqrt, abs, sign, min, max, the operators + - * / ^ and
// ?:); evaluated at the physical state. A model fitted in internal units (vehs/core/scaling.hpp)
// holds the same function of the internal state over its typical size, g(kx·x̃, ky·ỹ, ku·ũ)/c,
// made by rescaled().
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace vehs {

class UserFunction {
 public:
  /// Parses `text` over the variables x, y, u (white space is dropped). Throws vehs::Error with
  /// the parser's reason, or when the expression uses none of x, y, u.
  static std::shared_ptr<const UserFunction> parse(std::string_view text);

  /// The expression as written (without white space): the term's name in a model file.
  const std::string& text() const { return text_; }
  bool uses_x() const { return uses_[0]; }
  bool uses_y() const { return uses_[1]; }
  bool uses_u() const { return uses_[2]; }
  /// Factors (kx, ky, ku) applied to the arguments before evaluation (1, 1, 1 as parsed).
  const std::array<double, 3>& scales() const { return scales_; }
  /// Factor applied to the value (1 as parsed).
  double value_factor() const { return value_; }
  /// The same expression evaluated at (kx·x, ky·y, ku·u) and multiplied by kvalue, the factors
  /// compounding.
  std::shared_ptr<const UserFunction> rescaled(double kx, double ky, double ku, double kvalue = 1.0) const;

  /// g(x, y, u); safe to call from several threads at once.
  double operator()(double x, double y, double u = 0.0) const;

  /// The calling thread's parser of this function, found once: g(x, y, u) without the per-call
  /// lookup, for many evaluations in a row on one thread. Valid while the function lives and the
  /// thread evaluates no other function in between.
  class Local {
   public:
    double operator()(double x, double y, double u = 0.0) const;

   private:
    friend class UserFunction;
    Local(void* instance, const std::array<double, 3>& scales, double value)
        : instance_(instance), scales_(scales), value_(value) {}
    void* instance_;
    std::array<double, 3> scales_;
    double value_;
  };
  Local local() const;

 private:
  UserFunction() = default;
  std::string text_;
  std::array<bool, 3> uses_{};
  std::array<double, 3> scales_{1.0, 1.0, 1.0};
  double value_ = 1.0;
  std::uint64_t id_ = 0;  ///< the per-thread parser cache's key
};

}  // namespace vehs
