#include "vehs/core/parameters.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <utility>

#include "vehs/core/error.hpp"
#include "vehs/core/scaling.hpp"

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

std::optional<Location> term_of_effect_parameter(EffectId id, const std::string& param);

/// An effect's parameter: the term it stands for when the effect is term-like, else the effect's.
Location effect_location(EffectId id, const std::string& param, const std::string& name) {
  if (auto why = unknown_parameter(id, param); !why.empty()) throw Error("parameter '" + name + "'" + why);
  if (auto loc = term_of_effect_parameter(id, param)) return *loc;
  Location loc;
  loc.effect = true;
  loc.effect_id = id;
  loc.effect_param = param;
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
    const EffectId id = enum_from_string(kEffectNames, name.substr(0, dot), "parameter '" + name + "'");
    return effect_location(id, name.substr(dot + 1), name);
  }
  // a bare effect parameter ("mu"): the one effect of the catalogue that has it
  std::vector<EffectId> owners;
  for (const auto& spec : effect_catalogue())
    for (const auto& ps : spec.params)
      if (ps.name == name) owners.push_back(spec.id);
  if (owners.size() == 1) return effect_location(owners.front(), name, name);
  if (owners.size() > 1) {
    std::string list;
    for (EffectId id : owners) list += (list.empty() ? "" : ", ") + enum_to_string(kEffectNames, id) + "." + name;
    throw Error("parameter '" + name + "' is ambiguous (write one of: " + list + ")");
  }
  throw Error("unknown parameter '" + name +
              "' (known: beta, k<i>, 2D, 2Q, D, Q, drift[<term>], diffusion[<term>], <effect>.<param> "
              "or an effect's parameter alone, e.g. mu)");
}

/// The term (and its sign) a term-like effect's parameter stands for: coulomb_friction.mu is
/// −drift[sign(y)].
std::optional<Location> term_of_effect_parameter(EffectId id, const std::string& param) {
  if (!effect_spec(id).term_like) return std::nullopt;
  Effect unit;
  unit.id = id;
  unit.params[param] = 1.0;
  const EffectTerms t = effect_terms(unit);
  if (t.drift.size() + t.diffusion.size() != 1) return std::nullopt;
  const bool diffusion = t.drift.empty();
  const TermCoef& tc = diffusion ? t.diffusion.front() : t.drift.front();
  return term_location(diffusion, tc.term, tc.coef);
}

/// The physical name of a coefficient and the sign from coefficient to parameter: the paper's
/// (beta, k<i>, 2D, 2Q), a term-like effect's parameter (coulomb_friction.mu for sign(y)), else
/// the coefficient itself (drift[x^2], diffusion[x]).
std::pair<std::string, double> name_of(const Term& t, bool diffusion) {
  const bool mono = t.kind == TermKind::Monomial;
  if (!diffusion && mono && t.py == 1 && t.px == 0) return {"beta", -1.0};
  if (!diffusion && mono && t.py == 0) return {"k" + std::to_string(t.px), -1.0};
  if (diffusion && mono && t.py == 0 && t.px == 0) return {"2D", 1.0};
  if (diffusion && mono && t.py == 0 && t.px == 2) return {"2Q", 1.0};
  for (const auto& spec : effect_catalogue())
    for (const auto& ps : spec.params) {
      const auto loc = term_of_effect_parameter(spec.id, std::string(ps.name));
      if (loc && loc->diffusion == diffusion && loc->term == t)
        return {std::string(spec.name) + "." + std::string(ps.name), loc->sign};
    }
  return {std::string(diffusion ? "diffusion[" : "drift[") + t.name() + "]", 1.0};
}

}  // namespace

std::vector<PhysicalParameter> physical_parameters(const Model& m) {
  std::vector<PhysicalParameter> out;
  auto add = [&](const TermList& list, const std::map<std::string, double>& se, bool diffusion) {
    std::vector<PhysicalParameter> part;
    for (const auto& tc : list) {
      PhysicalParameter p;
      const auto [name, sign] = name_of(tc.term, diffusion);
      p.name = name;
      p.coefficient = std::string(diffusion ? "diffusion[" : "drift[") + tc.term.name() + "]";
      p.sign = sign;
      p.value = sign * tc.coef;
      if (auto it = se.find(tc.term.name()); it != se.end()) p.stderr_ = std::abs(sign) * it->second;
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

Dimension parameter_dimension(const std::string& name) {
  const Location loc = locate(name);
  // the unit conversion of scaling.hpp is the one source: a parameter scales as L^a T^b U^c
  auto scale = [&](const Scales& s) {
    if (loc.effect) return effect_parameter_scale(loc.effect_id, loc.effect_param, s);
    return loc.diffusion ? diffusion_coefficient_scale(loc.term, s) : drift_coefficient_scale(loc.term, s);
  };
  auto power = [&](double L, double T, double U) {
    Scales s;
    s.length = L, s.time = T, s.input = U;
    return static_cast<int>(std::lround(std::log2(scale(s))));
  };
  return {power(2.0, 1.0, 1.0), power(1.0, 2.0, 1.0), power(1.0, 1.0, 2.0)};
}

}  // namespace vehs
