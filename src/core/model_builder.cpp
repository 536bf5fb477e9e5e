#include "vehs/core/model_builder.hpp"

#include <cmath>

#include "vehs/core/error.hpp"
#include "vehs/core/parameters.hpp"

namespace vehs {

ModelBuilder& ModelBuilder::term(TermList& list, std::string_view name, double coef, const char* what) {
  const std::string w = where_ + ": " + what + "[\"" + std::string(name) + "\"]";
  Term t;
  try {
    t = Term::parse(name);
  } catch (const Error& e) {
    throw Error(where_ + ": " + what + ": " + e.what());
  }
  require(std::isfinite(coef), w + " must be finite");
  if (&list == &model_.diffusion) require(allowed_in_diffusion(t), where_ + ": diffusion term '" + t.name() + "' is not allowed");
  list.push_back({t, coef});
  canonicalize(list, where_ + ": " + what);
  return *this;
}

ModelBuilder& ModelBuilder::drift(std::string_view name, double coef) { return term(model_.drift, name, coef, "drift"); }

ModelBuilder& ModelBuilder::diffusion(std::string_view name, double coef) {
  return term(model_.diffusion, name, coef, "diffusion");
}

ModelBuilder& ModelBuilder::parameter(const std::string& name, double value) {
  try {
    set_parameter(model_, name, value);
  } catch (const Error& e) {
    throw Error(where_ + ": " + e.what());
  }
  return *this;
}

ModelBuilder& ModelBuilder::effect(std::string_view name, const std::map<std::string, double>& params) {
  Effect e;
  e.id = enum_from_string(kEffectNames, name, where_ + ": effect name");
  e.params = params;
  return effect(e);
}

ModelBuilder& ModelBuilder::effect(const Effect& e) {
  add_effect(model_, e, where_ + ": effect '" + e.name() + "'");
  return *this;
}

ModelBuilder& ModelBuilder::fit(const FitInfo& f) {
  model_.fit = f;
  return *this;
}

Model ModelBuilder::build() const {
  validate_model(model_, where_);
  return model_;
}

Model Model::paper(double beta, const std::map<int, double>& k, double two_D, double two_Q) {
  ModelBuilder b("paper model");
  b.parameter("beta", beta);
  for (const auto& [power, value] : k) b.parameter("k" + std::to_string(power), value);
  b.parameter("2D", two_D);
  if (two_Q != 0.0) b.parameter("2Q", two_Q);
  return b.build();
}

}  // namespace vehs
