#include "vehs/core/parameters.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "vehs/core/error.hpp"

namespace vehs {

namespace {

// A parameter name resolved to (drift or diffusion term, sign) or an effect parameter.
struct Location {
  bool diffusion = false;
  Term term;
  double sign = 1.0;
  bool effect = false;
  EffectId effect_id{};
  std::string effect_param;
};

Location term_location(bool diffusion, Term term, double sign) {
  Location loc;
  loc.diffusion = diffusion;
  loc.term = term;
  loc.sign = sign;
  return loc;
}

Location locate(const std::string& name) {
  Location loc;
  if (name == "beta") return term_location(false, Term::monomial(0, 1), -1.0);
  if (name == "2D" || name == "D") return term_location(true, Term::monomial(0, 0), name == "D" ? 0.5 : 1.0);
  if (name == "2Q" || name == "Q") return term_location(true, Term::monomial(2, 0), name == "Q" ? 0.5 : 1.0);
  if (name.size() >= 2 && name.size() <= 3 && name[0] == 'k' &&
      std::all_of(name.begin() + 1, name.end(), [](unsigned char c) { return std::isdigit(c); }))
    return term_location(false, Term::monomial(std::stoi(name.substr(1)), 0), -1.0);
  for (const char* prefix : {"drift[", "diffusion["}) {
    const std::string p(prefix);
    if (name.rfind(p, 0) == 0 && name.back() == ']') {
      loc.diffusion = p == "diffusion[";
      loc.term = Term::parse(name.substr(p.size(), name.size() - p.size() - 1));
      return loc;
    }
  }
  const auto dot = name.find('.');
  if (dot != std::string::npos) {
    loc.effect = true;
    loc.effect_id = enum_from_string(kEffectNames, name.substr(0, dot), "parameter '" + name + "'");
    loc.effect_param = name.substr(dot + 1);
    return loc;
  }
  throw Error("unknown parameter '" + name +
              "' (known: beta, k<i>, 2D, 2Q, D, Q, drift[<term>], diffusion[<term>], <effect>.<param>)");
}

std::string name_of(const Term& t, bool diffusion) {
  if (!diffusion) {
    if (t.kind == TermKind::Monomial && t.py == 1 && t.px == 0) return "beta";
    if (t.kind == TermKind::Monomial && t.py == 0) return "k" + std::to_string(t.px);
    return "drift[" + t.name() + "]";
  }
  if (t.kind == TermKind::Monomial && t.py == 0 && t.px == 0) return "2D";
  if (t.kind == TermKind::Monomial && t.py == 0 && t.px == 2) return "2Q";
  return "diffusion[" + t.name() + "]";
}

}  // namespace

std::vector<PhysicalParameter> physical_parameters(const Model& m) {
  std::vector<PhysicalParameter> out;
  auto add = [&](const TermList& list, const std::map<std::string, double>& se, bool diffusion) {
    std::vector<PhysicalParameter> part;
    for (const auto& tc : list) {
      PhysicalParameter p;
      p.name = name_of(tc.term, diffusion);
      const bool negate = !diffusion && tc.term.kind == TermKind::Monomial &&
                          ((tc.term.py == 1 && tc.term.px == 0) || tc.term.py == 0);
      p.value = negate ? -tc.coef : tc.coef;
      if (auto it = se.find(tc.term.name()); it != se.end()) p.stderr_ = it->second;
      part.push_back(p);
    }
    // beta first, then k_i by power, then the rest in canonical term order
    std::stable_sort(part.begin(), part.end(), [](const auto& a, const auto& b) {
      auto rank = [](const PhysicalParameter& q) {
        if (q.name == "beta") return 0;
        if (q.name[0] == 'k') return 1;
        return 2;
      };
      return rank(a) < rank(b);
    });
    out.insert(out.end(), part.begin(), part.end());
  };
  add(m.drift, m.drift_stderr, false);
  add(m.diffusion, m.diffusion_stderr, true);
  for (const auto& e : m.effects)
    for (const auto& [k, v] : e.params) {
      PhysicalParameter p;
      p.name = e.name() + "." + k;
      p.value = v;
      if (auto it = e.stderr_.find(k); it != e.stderr_.end()) p.stderr_ = it->second;
      out.push_back(p);
    }
  return out;
}

double get_parameter(const Model& m, const std::string& name) {
  const Location loc = locate(name);
  if (loc.effect) {
    for (const auto& e : m.effects)
      if (e.id == loc.effect_id) return e.param(loc.effect_param);
    throw Error("parameter '" + name + "': the model has no effect '" +
                enum_to_string(kEffectNames, loc.effect_id) + "'");
  }
  return loc.sign * coefficient(loc.diffusion ? m.diffusion : m.drift, loc.term);
}

void set_parameter(Model& m, const std::string& name, double value) {
  require(std::isfinite(value), "parameter '" + name + "' must be finite");
  const Location loc = locate(name);
  if (loc.effect) {
    for (auto& e : m.effects)
      if (e.id == loc.effect_id) {
        if (!e.params.count(loc.effect_param))
          throw Error("parameter '" + name + "': effect has no parameter '" + loc.effect_param + "'");
        e.params[loc.effect_param] = value;
        return;
      }
    throw Error("parameter '" + name + "': the model has no effect '" +
                enum_to_string(kEffectNames, loc.effect_id) + "'");
  }
  TermList& list = loc.diffusion ? m.diffusion : m.drift;
  for (auto& tc : list)
    if (tc.term == loc.term) {
      tc.coef = value / loc.sign;
      return;
    }
  list.push_back({loc.term, value / loc.sign});
  canonicalize(list, name);
}

}  // namespace vehs
