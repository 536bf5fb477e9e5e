#include "vehs/core/user_function.hpp"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cctype>
#include <unordered_map>

#include <muParser.h>

#include "vehs/core/error.hpp"

namespace vehs {

namespace {

/// A parser bound to its own copy of the variables: one per thread and function.
struct Instance {
  double x = 0.0, y = 0.0, u = 0.0;
  mu::Parser parser;

  explicit Instance(const std::string& text) {
    parser.DefineVar("x", &x);
    parser.DefineVar("y", &y);
    parser.DefineVar("u", &u);
    parser.SetExpr(text);
  }
};

std::uint64_t next_id() {
  static std::atomic<std::uint64_t> counter{1};
  return counter++;
}

/// The thread's parser of function `id` (built on first use; the cache is bounded).
Instance& instance(std::uint64_t id, const std::string& text) {
  thread_local std::unordered_map<std::uint64_t, std::unique_ptr<Instance>> cache;
  auto it = cache.find(id);
  if (it != cache.end()) return *it->second;
  if (cache.size() >= 512) cache.clear();
  return *cache.emplace(id, std::make_unique<Instance>(text)).first->second;
}

}  // namespace

std::shared_ptr<const UserFunction> UserFunction::parse(std::string_view text) {
  std::string t;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) t += c;
  std::shared_ptr<UserFunction> f(new UserFunction());
  f->text_ = t;
  f->id_ = next_id();
  try {
    Instance probe(t);
    const auto used = probe.parser.GetUsedVar();  // parses; throws on unknown names
    f->uses_ = {used.count("x") > 0, used.count("y") > 0, used.count("u") > 0};
    probe.parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw Error("expression '" + std::string(text) + "': " + e.GetMsg());
  }
  if (!(f->uses_[0] || f->uses_[1] || f->uses_[2]))
    throw Error("expression '" + std::string(text) + "' uses none of x, y, u (a constant is the term \"1\")");
  return f;
}

std::shared_ptr<const UserFunction> UserFunction::rescaled(double kx, double ky, double ku, double kvalue) const {
  // a round trip (to internal units and back) returns the physical function exactly, so that it
  // equals the parsed one: 1e-9 · 1e9 is 1 + 2.2e-16 in floating point
  auto compound = [](double a, double b) {
    const double c = a * b;
    return std::abs(c - 1.0) < 1e-12 ? 1.0 : c;
  };
  std::shared_ptr<UserFunction> f(new UserFunction(*this));
  f->scales_ = {compound(scales_[0], kx), compound(scales_[1], ky), compound(scales_[2], ku)};
  f->value_ = compound(value_, kvalue);
  return f;  // same text: the per-thread parsers are shared
}

double UserFunction::operator()(double x, double y, double u) const { return local()(x, y, u); }

UserFunction::Local UserFunction::local() const { return Local(&instance(id_, text_), scales_, value_); }

double UserFunction::Local::operator()(double x, double y, double u) const {
  Instance& in = *static_cast<Instance*>(instance_);
  in.x = scales_[0] * x;
  in.y = scales_[1] * y;
  in.u = scales_[2] * u;
  return value_ * in.parser.Eval();
}

}  // namespace vehs
