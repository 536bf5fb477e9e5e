#include "vehs/diagnose/lens.hpp"

#include <algorithm>
#include <sstream>

#include "vehs/effects/from_model.hpp"

namespace vehs::diagnose {

CompiledTerms::CompiledTerms(const TermList& terms) {
  for (const auto& tc : terms) {
    if (tc.coef == 0.0) continue;
    switch (tc.term.kind) {
      case TermKind::Monomial:
        mono_.push_back({tc.term.px, tc.term.py, tc.coef});
        max_px_ = std::max(max_px_, tc.term.px);
        max_py_ = std::max(max_py_, tc.term.py);
        break;
      case TermKind::SignY: sign_ += tc.coef; break;
      case TermKind::YAbsY: yabs_ += tc.coef; break;
      case TermKind::Drive: u_ += tc.coef; break;
      case TermKind::User: user_.push_back(tc); break;
    }
  }
}

bool CompiledTerms::depends_on_y() const {
  if (sign_ != 0.0 || yabs_ != 0.0) return true;
  for (const auto& tc : user_)
    if (tc.term.depends_on_y()) return true;
  for (const auto& m : mono_)
    if (m.py > 0) return true;
  return false;
}

namespace {
// powers z^0..z^n into p (n <= 64)
inline void powers(double z, int n, double* p) {
  p[0] = 1.0;
  for (int i = 1; i <= n; ++i) p[i] = p[i - 1] * z;
}
inline double sgn(double y) { return static_cast<double>((y > 0) - (y < 0)); }
}  // namespace

double CompiledTerms::value(double x, double y, double u) const {
  double xp[65], yp[65];
  powers(x, max_px_, xp);
  powers(y, max_py_, yp);
  double s = 0.0;
  for (const auto& m : mono_) s += m.c * xp[m.px] * yp[m.py];
  if (sign_ != 0.0) s += sign_ * sgn(y);
  if (yabs_ != 0.0) s += yabs_ * y * std::abs(y);
  if (u_ != 0.0) s += u_ * u;
  for (const auto& tc : user_) s += tc.coef * tc.term.value(x, y, u);
  return s;
}

double CompiledTerms::d_dy(double x, double y, double w) const {
  double xp[65], yp[65];
  powers(x, max_px_, xp);
  powers(y, max_py_, yp);
  double s = 0.0;
  for (const auto& m : mono_)
    if (m.py > 0) s += m.c * m.py * xp[m.px] * yp[m.py - 1];
  if (sign_ != 0.0 && std::abs(y) < w) s += sign_ / w;
  if (yabs_ != 0.0) s += yabs_ * 2.0 * std::abs(y);
  for (const auto& tc : user_)  // over the kernel's width, as sign(y) (w = 0: its derivative)
    s += tc.coef * (w > 0.0 ? (tc.term.value(x, y + w, 0.0) - tc.term.value(x, y - w, 0.0)) / (2.0 * w)
                            : tc.term.d_dy(x, y));
  return s;
}

double CompiledTerms::d2_dy2(double x, double y) const {
  double xp[65], yp[65];
  powers(x, max_px_, xp);
  powers(y, max_py_, yp);
  double s = 0.0;
  for (const auto& m : mono_)
    if (m.py > 1) s += m.c * m.py * (m.py - 1) * xp[m.px] * yp[m.py - 2];
  if (yabs_ != 0.0) s += yabs_ * 2.0 * sgn(y);
  for (const auto& tc : user_) s += tc.coef * tc.term.d2_dy2(x, y);
  return s;
}

double CompiledTerms::d_dx(double x, double y) const {
  double xp[65], yp[65];
  powers(x, max_px_, xp);
  powers(y, max_py_, yp);
  double s = 0.0;
  for (const auto& m : mono_)
    if (m.px > 0) s += m.c * m.px * xp[m.px - 1] * yp[m.py];
  for (const auto& tc : user_) s += tc.coef * tc.term.d_dx(x, y);
  return s;
}

ExplicitForces::ExplicitForces(const Model& m) {
  for (const auto& e : m.effects) {
    if (e.id == EffectId::ImpactStop) {
      has_stop = true;
      stop = effects::from_effect<effects::ImpactStop>(e);
    } else if (e.id == EffectId::HarmonicForcing) {
      harmonic = true;
      forcing = effects::from_effect<effects::HarmonicForcing>(e);
    }
  }
}

std::string Lens::describe() const {
  std::ostringstream os;
  os.precision(6);
  if (kinematics == Kinematics::Central)
    os << "central (ULI) kinematics, stride " << stride << ": v = (x[i+k] - x[i-k])/2h, a = (x[i+k] - 2x[i] + "
       << "x[i-k])/h^2, h = " << h() << "; whitening variance (2/3) a22/h";
  else
    os << "forward kinematics: v = (x[i+1] - x[i])/dt, a = (x[i+2] - 2x[i+1] + x[i])/dt^2, dt = " << dt
       << "; whitening variance a22/dt";
  if (sensor_noise_sd > 0.0) os << " + 6 s^2/h^4 (sensor noise s = " << sensor_noise_sd << ")";
  return os.str();
}

std::string Lens::invalid_reason() const {
  if (!(dt > 0.0) || !std::isfinite(dt)) return "the sampling interval must be positive";
  if (stride < 1) return "the stride must be >= 1";
  if (kinematics == Kinematics::Forward && stride != 1) return "forward kinematics have stride 1";
  if (!(sensor_noise_sd >= 0.0) || !std::isfinite(sensor_noise_sd)) return "the sensor noise must be >= 0";
  return "";
}

ModelLens::ModelLens(const Model& model, const Lens& lens)
    : lens_(lens), drift_(model.drift), diffusion_(model.diffusion), forces_(model),
      noise_var_(lens.noise_variance()) {
  for (const auto& e : model.effects)
    if (e.id == EffectId::ElectromechanicalCoupling || e.id == EffectId::ColoredNoise) hidden_ = true;
}

}  // namespace vehs::diagnose
