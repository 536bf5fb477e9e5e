#include "tools/identify_figures.hpp"

#include <cmath>
#include <filesystem>
#include <cstdio>
#include <sstream>
#include <tuple>

#include "tools/figures.hpp"
#include "tools/measurement_config.hpp"
#include "tools/table.hpp"
#include "vehs/identify/binned.hpp"

namespace vehs::tools {

namespace {

/// A linear function of the estimates: its value and gradient by parameter name.
struct Linear {
  double value = 0.0;
  std::vector<std::pair<std::string, double>> gradient;
};

/// Standard error of a linear function from the covariance (or the standard errors alone).
double stderr_of(const Linear& f, const Model& m) {
  const auto& c = m.covariance;
  double var = 0.0;
  if (!c.empty()) {
    for (const auto& [a, ga] : f.gradient)
      for (const auto& [b, gb] : f.gradient) {
        const auto i = c.index_of(a), j = c.index_of(b);
        if (i < c.size() && j < c.size()) var += ga * gb * c(i, j);
      }
    return std::sqrt(std::max(var, 0.0));
  }
  for (const auto& [a, ga] : f.gradient) {
    const bool drift = a.rfind("drift[", 0) == 0;
    const std::string term = a.substr(drift ? 6 : 10, a.size() - (drift ? 7 : 11));
    const auto& se = drift ? m.drift_stderr : m.diffusion_stderr;
    if (auto it = se.find(term); it != se.end()) var += ga * ga * it->second * it->second;
  }
  return std::sqrt(var);
}

/// Σ coef·term over the terms `keep` selects, as a linear function of the coefficients.
template <class Keep>
Linear terms_at(const TermList& list, const char* kind, double x, double y, Keep keep) {
  Linear f;
  for (const auto& tc : list) {
    if (!keep(tc.term)) continue;
    const double phi = tc.term.value(x, y, 0.0);
    f.value += tc.coef * phi;
    f.gradient.emplace_back(std::string(kind) + "[" + tc.term.name() + "]", phi);
  }
  return f;
}

/// U(x) = −∫_0^x (x-only drift)(s) ds: monomials x^p integrate to x^(p+1)/(p+1).
Linear potential_at(const TermList& drift, double x) {
  Linear f;
  for (const auto& tc : drift) {
    if (tc.term.kind != TermKind::Monomial || tc.term.py != 0) continue;
    const double g = -ipow(x, tc.term.px + 1) / (tc.term.px + 1);
    f.value += tc.coef * g;
    f.gradient.emplace_back("drift[" + tc.term.name() + "]", g);
  }
  return f;
}

void add_points(Table& t, const identify::BinnedCurve& c) {
  for (std::size_t i = 0; i < c.at.size(); ++i)
    if (std::isfinite(c.mean[i])) t.add_row({c.at[i], c.mean[i], c.se[i]});
}

/// The diffusion panel's title: the sensor noise removed from the binned data (its share of
/// the raw), or that the bins were dropped.
std::string diffusion_title(const identify::BinnedEstimates& km) {
  if (km.noise_sd == 0) return "diffusion a22(x, 0)";
  char buf[160];
  std::snprintf(buf, sizeof buf,
                km.diffusion_bins_dropped > 0 ? "diffusion a22(x, 0); no data: sensor noise sd %.3g is %.3g %% of the raw"
                                              : "diffusion a22(x, 0); data less sensor noise sd %.3g (%.3g %% of the raw)",
                km.noise_sd, 100 * km.noise_share);
  return buf;
}

/// The sensor noise sd of the fit with its standard error: the likelihood's measurement_sd when
/// the model has one, else the moment fit's estimate (no standard error).
std::pair<double, double> sensor_noise(const Model& m) {
  if (!m.fit) return {0.0, 0.0};
  if (const auto& l = m.fit->likelihood; l && l->measurement_sd > 0) {
    double se = 0.0;
    for (std::size_t i = 0; i < l->parameters.size(); ++i)
      if (l->parameters[i] == "measurement_sd" && l->covariance.size() == l->parameters.size() * l->parameters.size())
        se = std::sqrt(std::max(0.0, l->covariance[i * l->parameters.size() + i]));
    return {l->measurement_sd, se};
  }
  return {m.fit->sampling.sensor_noise_sd, 0.0};
}

}  // namespace

std::string identify_figure(const std::string& dir, const Model& model, const Dataset& data,
                            const nlohmann::json& units) {
  // (the folder is created by the first staged file: inside a run's transaction it goes with a rollback)
  identify::BinnedOptions bo;
  std::tie(bo.noise_sd, bo.noise_sd_se) = sensor_noise(model);
  const identify::BinnedEstimates km = identify::binned_estimates(data, model, bo);
  const auto x_only = [](const Term& t) { return !t.depends_on_y() && !t.depends_on_u(); };
  const auto y_part = [](const Term& t) { return t.depends_on_y() && !t.depends_on_u(); };
  const auto all = [](const Term&) { return true; };
  Table curves({"x", "drift_x", "drift_x_se", "U", "U_se", "a22", "a22_se", "v", "drift_v", "drift_v_se"});
  const double xlo = km.drift_x.at.front(), xhi = km.drift_x.at.back();
  const double vlo = km.drift_v.at.front(), vhi = km.drift_v.at.back();
  const int n = 200;
  for (int i = 0; i <= n; ++i) {
    const double x = xlo + (xhi - xlo) * i / n, v = vlo + (vhi - vlo) * i / n;
    const Linear fx = terms_at(model.drift, "drift", x, 0.0, x_only), u = potential_at(model.drift, x);
    const Linear q = terms_at(model.diffusion, "diffusion", x, 0.0, all);
    const Linear fv = terms_at(model.drift, "drift", 0.0, v, y_part);
    curves.add_row({x, fx.value, stderr_of(fx, model), u.value, stderr_of(u, model), q.value, stderr_of(q, model), v,
                    fv.value, stderr_of(fv, model)});
  }
  curves.write_csv(dir + "/identify_fit_model.csv");
  Table px({"x", "mean", "se"}), pv({"v", "mean", "se"}), pd({"x", "mean", "se"});
  add_points(px, km.drift_x);
  add_points(pv, km.drift_v);
  add_points(pd, km.diffusion);
  px.write_csv(dir + "/identify_fit_km_x.csv");
  pv.write_csv(dir + "/identify_fit_km_v.csv");
  pd.write_csv(dir + "/identify_fit_km_diffusion.csv");
  const std::string X = with_unit("x", "x", units), V = with_unit("y", "v", units);
  const std::string B = with_unit("force per unit mass", "b2", units), A = with_unit("a22", "a22", units);
  const std::string band = " with filledcurves fc rgb '#c6dbef' title 'model, 95 % band'";
  const std::string line = " with lines lw 2 lc rgb '#2171b5' title 'model'";
  const std::string pts = " with yerrorbars pt 7 ps 0.5 lc rgb '#cb181d' title 'data, binned (± se)'";
  std::ostringstream gp;
  gp << "set multiplot layout 2,2\nset grid\nset key below horizontal font ',10'\n"
     << "set title 'drift at y = 0: x-only terms'\nset xlabel " << gnuplot_quote(X) << "\nset ylabel " << gnuplot_quote(B) << "\n"
     << "plot 'identify_fit_model.csv' skip 1 using 1:($2-1.96*$3):($2+1.96*$3)" << band << ", '' skip 1 using 1:2"
     << line << ", 'identify_fit_km_x.csv' skip 1 using 1:2:3" << pts << "\n"
     << "set title " << gnuplot_quote(std::string("drift at x = 0: velocity terms") + (model.uses_drive() ? " (data: input terms removed)" : ""))
     << "\nset xlabel " << gnuplot_quote(V) << "\n"
     << "plot 'identify_fit_model.csv' skip 1 using 8:($9-1.96*$10):($9+1.96*$10)" << band << ", '' skip 1 using 8:9"
     << line << ", 'identify_fit_km_v.csv' skip 1 using 1:2:3" << pts << "\n"
     << "set title 'potential U(x) = -integral of the x-only drift'\nset xlabel " << gnuplot_quote(X)
     << "\nset ylabel " << gnuplot_quote(with_unit("U", "v2", units)) << "\n"
     << "plot 'identify_fit_model.csv' skip 1 using 1:($4-1.96*$5):($4+1.96*$5)" << band << ", '' skip 1 using 1:4"
     << line << "\n"
     << "set title " << gnuplot_quote(diffusion_title(km)) << "\nset xlabel " << gnuplot_quote(X) << "\nset ylabel " << gnuplot_quote(A) << "\n"
     << "plot 'identify_fit_model.csv' skip 1 using 1:($6-1.96*$7):($6+1.96*$7)" << band << ", '' skip 1 using 1:6"
     << line << (pd.rows.empty() ? "" : ", 'identify_fit_km_diffusion.csv' skip 1 using 1:2:3" + pts) << "\nunset multiplot\n";
  return render_figure(dir, "identify_fit", gp.str(), "svg", 1100, 860);
}

}  // namespace vehs::tools
