#include "vehs/sim/detail/model_system.hpp"

#include <cmath>
#include <map>

#include "vehs/core/error.hpp"
#include "vehs/effects/from_model.hpp"

namespace vehs::sim::detail {

XPolynomial XPolynomial::from_coefficients(const std::vector<double>& c) {
  XPolynomial p;
  std::size_t n = c.size();
  while (n > 0 && c[n - 1] == 0.0) --n;
  for (std::size_t i = 0; i < n; ++i) (i % 2 == 0 ? p.even : p.odd).push_back(c[i]);
  while (!p.even.empty() && p.even.back() == 0.0) p.even.pop_back();
  while (!p.odd.empty() && p.odd.back() == 0.0) p.odd.pop_back();
  return p;
}

std::vector<double> XPolynomial::coefficients() const {
  std::vector<double> c(std::max(2 * even.size(), 2 * odd.size()), 0.0);
  for (std::size_t k = 0; k < even.size(); ++k) c[2 * k] = even[k];
  for (std::size_t k = 0; k < odd.size(); ++k) c[2 * k + 1] = odd[k];
  while (!c.empty() && c.back() == 0.0) c.pop_back();
  return c;
}

XPolynomial XPolynomial::derivative() const {
  const auto c = coefficients();
  std::vector<double> d(c.size() > 0 ? c.size() - 1 : 0, 0.0);
  for (std::size_t n = 1; n < c.size(); ++n) d[n - 1] = static_cast<double>(n) * c[n];
  return from_coefficients(d);
}

int XPolynomial::degree() const { return static_cast<int>(coefficients().size()) - 1; }

double XPolynomial::leading_coefficient() const {
  const auto c = coefficients();
  return c.empty() ? 0.0 : c.back();
}

double XPolynomial::eval(double x) const {
  const auto c = coefficients();
  double r = 0.0;
  for (std::size_t n = c.size(); n-- > 0;) r = r * x + c[n];
  return r;
}

double YXPolynomial::eval(double x, double y, double u) const {
  double r = 0.0;
  for (std::size_t j = by_ypow.size(); j-- > 0;) r = r * y + by_ypow[j].eval(x);
  r += y_abs_y * y * std::abs(y) + abs_y * std::abs(y) + sign_y * ((y > 0) - (y < 0)) + drive * u;
  for (const auto& p : user) r += p.at(x, y, u);
  return r;
}

namespace {

// Builder: dense coefficients by (power of y, power of x).
struct DenseYX {
  std::map<int, std::vector<double>> by_ypow;
  double y_abs_y = 0.0, abs_y = 0.0, sign_y = 0.0, drive = 0.0;
  std::vector<YXPolynomial::UserPart> user;

  void add(int px, int py, double c) {
    if (c == 0.0) return;
    auto& v = by_ypow[py];
    if (v.size() <= static_cast<std::size_t>(px)) v.resize(static_cast<std::size_t>(px) + 1, 0.0);
    v[static_cast<std::size_t>(px)] += c;
  }
  YXPolynomial build() const {
    YXPolynomial p;
    int max_j = -1;
    for (const auto& [j, c] : by_ypow)
      if (!XPolynomial::from_coefficients(c).empty()) max_j = std::max(max_j, j);
    p.by_ypow.resize(static_cast<std::size_t>(max_j + 1));
    for (const auto& [j, c] : by_ypow)
      if (j <= max_j) p.by_ypow[static_cast<std::size_t>(j)] = XPolynomial::from_coefficients(c);
    p.y_abs_y = y_abs_y;
    p.abs_y = abs_y;
    p.sign_y = sign_y;
    p.drive = drive;
    p.user = user;
    p.has_nonpoly = y_abs_y != 0.0 || abs_y != 0.0 || sign_y != 0.0 || !user.empty();
    return p;
  }
};

struct Compiled {
  DenseYX f, fx, fy, fyy;
};

Compiled compile_terms(const TermList& terms) {
  Compiled c;
  for (const auto& tc : terms) {
    const double k = tc.coef;
    const Term& t = tc.term;
    switch (t.kind) {
      case TermKind::Monomial:
        c.f.add(t.px, t.py, k);
        if (t.px > 0) c.fx.add(t.px - 1, t.py, k * t.px);
        if (t.py > 0) c.fy.add(t.px, t.py - 1, k * t.py);
        if (t.py > 1) c.fyy.add(t.px, t.py - 2, k * t.py * (t.py - 1));
        break;
      case TermKind::SignY: c.f.sign_y += k; break;  // derivatives 0 almost everywhere
      case TermKind::YAbsY:
        c.f.y_abs_y += k;
        c.fy.abs_y += 2.0 * k;
        c.fyy.sign_y += 2.0 * k;
        break;
      case TermKind::Drive: c.f.drive += k; break;
      case TermKind::User:
        if (k == 0.0) break;
        c.f.user.push_back({k, t, YXPolynomial::UserPart::Value});
        c.fx.user.push_back({k, t, YXPolynomial::UserPart::Dx});
        c.fy.user.push_back({k, t, YXPolynomial::UserPart::Dy});
        c.fyy.user.push_back({k, t, YXPolynomial::UserPart::Dyy});
        break;
    }
  }
  return c;
}

/// The simulator's dynamic effects (term-like ones are terms by now).
void compile_effects(const Model& m, const std::string& where, CompiledModel& cm) {
  for (const auto& e : m.effects) {
    switch (e.id) {
      case EffectId::ImpactStop:
        cm.impact = true;
        cm.stop = effects::from_effect<effects::ImpactStop>(e);
        break;
      case EffectId::HarmonicForcing:
        cm.harmonic = true;
        cm.forcing = effects::from_effect<effects::HarmonicForcing>(e);
        break;
      case EffectId::ElectromechanicalCoupling:
        cm.electro = true;
        cm.lambda = e.param("lambda");
        cm.coupling = e.param("coupling");
        break;
      case EffectId::ColoredNoise:
        cm.colored = true;
        cm.tau = e.param("tau");
        cm.intensity = e.param("intensity");
        break;
      default:
        throw Error(where + ": effect '" + e.name() + "' should have been expanded into terms; the simulator cannot treat it");
    }
  }
}

/// The fast polynomial family (CompiledModel::Fast): no extras, drift = p(x) + y·d(x),
/// a22 = a(x), with small enough degrees; otherwise not eligible.
void compile_fast(CompiledModel& cm) {
  if (cm.has_extras || cm.drift.has_nonpoly || cm.diffusion.has_nonpoly || cm.diffusion.by_ypow.size() > 1 ||
      cm.drift.by_ypow.size() > 2)
    return;
  const std::vector<double> pc = cm.drift.by_ypow.empty() ? std::vector<double>{} : cm.drift.by_ypow[0].coefficients();
  const std::vector<double> dc = cm.drift.by_ypow.size() > 1 ? cm.drift.by_ypow[1].coefficients() : std::vector<double>{};
  const std::vector<double> ac =
      cm.diffusion.by_ypow.empty() ? std::vector<double>{} : cm.diffusion.by_ypow[0].coefficients();
  if (!(pc.size() <= 12 && dc.size() <= 3 && ac.size() <= 5)) return;
  auto& f = cm.fast;
  f.eligible = true;
  f.k = std::max<int>(1, static_cast<int>((pc.size() + 1) / 2));
  for (std::size_t n = 0; n < pc.size(); ++n) (n % 2 == 0 ? f.even[n / 2] : f.odd[n / 2]) = pc[n];
  for (std::size_t n = 1; n < pc.size(); ++n) {
    const std::size_t pw = n - 1;  // power of x in the derivative
    (pw % 2 == 0 ? f.deven[pw / 2] : f.dodd[pw / 2]) = static_cast<double>(n) * pc[n];
  }
  for (std::size_t n = 0; n < dc.size(); ++n) f.damping[n] = dc[n];
  for (std::size_t n = 0; n < ac.size(); ++n) f.a22[n] = ac[n];
  for (std::size_t n = 1; n < ac.size(); ++n) f.da22[n - 1] = static_cast<double>(n) * ac[n];
  for (double c : f.even) f.has_even = f.has_even || c != 0.0;
  f.damping_poly = f.damping[1] != 0.0 || f.damping[2] != 0.0;
  f.a22_even2 = f.a22[1] == 0.0 && f.a22[3] == 0.0 && f.a22[4] == 0.0;
  f.additive = f.a22_even2 && f.a22[2] == 0.0;
  f.sigma0 = f.additive && f.a22[0] > 0.0 ? std::sqrt(f.a22[0]) : 0.0;
}

}  // namespace

CompiledModel CompiledModel::from_model(const Model& m, const std::string& where) {
  CompiledModel cm;
  const Compiled d = compile_terms(m.drift);
  cm.drift = d.f.build();
  cm.drift_dx = d.fx.build();
  cm.drift_dy = d.fy.build();
  cm.drift_dyy = d.fyy.build();
  for (const auto& tc : m.diffusion)
    if (!allowed_in_diffusion(tc.term))
      throw Error(where + ": diffusion term '" + tc.term.name() + "' cannot be simulated");
  const Compiled a = compile_terms(m.diffusion);
  cm.diffusion = a.f.build();
  cm.diffusion_dx = a.fx.build();
  cm.diffusion_dy = a.fy.build();
  cm.diffusion_dyy = a.fyy.build();
  cm.beta = -coefficient(m.drift, Term::monomial(0, 1));
  cm.noise_depends_on_y = cm.diffusion.depends_on_y();
  bool only_constant = true;
  for (const auto& tc : m.diffusion)
    if (!(tc.term.kind == TermKind::Monomial && tc.term.px == 0 && tc.term.py == 0) && tc.coef != 0.0)
      only_constant = false;
  cm.additive_noise = only_constant;
  if (only_constant) {
    const double a0 = coefficient(m.diffusion, Term::monomial(0, 0));
    require(a0 >= 0.0, where + ": diffusion['1'] = " + std::to_string(a0) +
                           " is negative (a22 is a variance rate and must be >= 0)");
    cm.constant_sigma = std::sqrt(a0);
  }
  compile_effects(m, where, cm);
  cm.has_extras = cm.drift.drive != 0.0 || cm.impact || cm.harmonic || cm.electro || cm.colored;
  compile_fast(cm);
  return cm;
}

}  // namespace vehs::sim::detail
