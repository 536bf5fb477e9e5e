#pragma once
// Building a Model in C++ without JSON: terms by name, physical parameters by name (beta, k<i>,
// 2D, 2Q, … of vehs/core/parameters.hpp), effects by name with their parameters — each checked
// as a model file would be (term grammar, duplicates, finite coefficients, diffusion terms,
// effect parameters and their bounds).
//
//   const vehs::Model m = vehs::ModelBuilder()
//                             .drift("x", 1.0).drift("x^3", -1.0).parameter("beta", 0.1)
//                             .diffusion("1", 0.02).diffusion("x^2", 0.01)
//                             .effect("coulomb_friction", {{"mu", 0.05}})
//                             .build();
//   // the paper's k_i (b2 = −β y − Σ k_i x^i), not raw drift coefficients (docs/model-file.md)
//   const vehs::Model paper = vehs::Model::paper(0.1, {{1, 1.0}, {3, -7.7}, {5, 16.3}, {7, -12.5}, {9, 3.1}},
//                                                0.02, 0.01);
#include <map>
#include <string>
#include <string_view>

#include "vehs/core/fit_info.hpp"
#include "vehs/core/model.hpp"

namespace vehs {

class ModelBuilder {
 public:
  /// `where` prefixes error messages.
  explicit ModelBuilder(std::string where = "model") : where_(std::move(where)) {}

  /// Adds the drift term `term` ("x^3", "x^2*y", "sign(y)", "u", …) with coefficient `coef`.
  ModelBuilder& drift(std::string_view term, double coef);
  /// Adds the diffusion term `term` (a22; not u or sign(y)).
  ModelBuilder& diffusion(std::string_view term, double coef);
  /// Sets a parameter by physical name (beta, k`<i>`, 2D, 2Q, D, Q, drift[..], diffusion[..]).
  ModelBuilder& parameter(const std::string& name, double value);
  /// Adds an effect of the catalogue by name; missing parameters take their defaults or are an
  /// error. Term-like effects become their terms.
  ModelBuilder& effect(std::string_view name, const std::map<std::string, double>& params = {});
  ModelBuilder& effect(const Effect& effect);
  /// States how the model was fitted (what diagnose reads; a fitted model from identify has it).
  ModelBuilder& fit(const FitInfo& fit);

  /// The model, checked (validate_model). Throws vehs::Error prefixed with `where`.
  Model build() const;

 private:
  ModelBuilder& term(TermList& list, std::string_view name, double coef, const char* what);
  Model model_;
  std::string where_;
};

}  // namespace vehs
