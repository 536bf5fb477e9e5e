#include "tools/diagnosis_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "tools/diagnosis_file.hpp"
#include "tools/figures.hpp"
#include "tools/measurement_config.hpp"
#include "tools/report_validation.hpp"
#include "tools/table.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/parameter_units.hpp"

namespace vehs::tools {

using namespace vehs::diagnose;

namespace {

std::string g(double v, int digits = 4) { return std::isfinite(v) ? vehs::detail::format_number(v, digits) : "-"; }

std::string pm(double v, double se) { return g(v) + " ± " + g(se, 2); }

/// A label safe for a CSV cell read by gnuplot.
std::string label_text(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '"' || c == '\n' || c == '\'') c = ' ';
  return s;
}

const char* kDiverging =
    "set palette defined (-5 '#2166ac', -2 '#92c5de', 0 '#f7f7f7', 2 '#f4a582', 5 '#b2182b')\n"
    "set cbrange [-5:5]\n";

Table curve_table(const Curve& c, const std::string& at_name, bool with_reference, std::size_t first = 0) {
  std::vector<std::string> cols{at_name, "data", "data_se", "twin", "twin_se"};
  if (with_reference) cols.push_back("reference");
  Table t(cols);
  for (std::size_t i = first; i < c.at.size(); ++i) {
    std::vector<double> row{c.at[i], c.data[i], c.data_se[i], c.twin[i], c.twin_se[i]};
    if (with_reference) row.push_back(i < c.reference.size() ? c.reference[i] : std::nan(""));
    t.add_row(row);
  }
  return t;
}

/// Points of a curve beyond which error bars are thinned (dense bars merge into a band).
constexpr std::size_t kDenseCurve = 60;

/// gnuplot body of a data-vs-twins curve: twin band ±2 se, twin line, data points with error bars.
std::string band_plot(const std::string& csv, const std::string& title, const std::string& xlabel,
                      const std::string& ylabel, bool logx, bool logy, const std::string& extra = "",
                      std::size_t points = 0) {
  std::ostringstream os;
  os << "set title " << gnuplot_quote(title) << "\nset xlabel " << gnuplot_quote(xlabel) << "\nset ylabel "
     << gnuplot_quote(ylabel) << "\n"
     << "set key below horizontal\nset grid\n";  // the legend under the plot, off the data
  if (logx) os << "set logscale x\n";
  if (logy) os << "set logscale y\nset format y '%g'\n";
  const std::string lo = logy ? "($4-2*$5 > 0 ? $4-2*$5 : $4/10)" : "($4-2*$5)";
  os << "plot " << gnuplot_quote(csv) << " skip 1 using 1:" << lo << ":($4+2*$5) with filledcurves fc rgb '#c6dbef' "
     << "title 'model twins ± 2 se', \\\n"
     << "  '' skip 1 using 1:4 with lines lw 2 lc rgb '#2171b5' title 'model twins', \\\n";
  if (points > kDenseCurve) {  // the data as a line, error bars on every k-th point
    const std::size_t every = (points + kDenseCurve - 1) / (kDenseCurve / 2);
    os << "  '' skip 1 using 1:2 with lines lw 1.5 lc rgb '#cb181d' title 'data', \\\n"
       << "  '' skip 1 every " << every << " using 1:2:3 with yerrorbars pt 7 ps 0.5 lc rgb '#cb181d' "
       << "title 'data ± se (every " << every << "th point)'" << extra << "\n";
  } else {
    os << "  '' skip 1 using 1:2:3 with yerrorbars pt 7 ps 0.4 lc rgb '#cb181d' title 'data ± se'" << extra << "\n";
  }
  return os.str();
}

}  // namespace

namespace {
/// "mu = 0.03 ± 0.004, ..." of fitted parameters.
std::string params_text(const std::map<std::string, double>& params, const std::map<std::string, double>& stderrs) {
  std::string text;
  for (const auto& [key, value] : params) {
    if (!text.empty()) text += ", ";
    text += key + " = " + g(value);
    if (auto se = stderrs.find(key); se != stderrs.end()) text += " ± " + g(se->second, 2);
  }
  return text;
}
}  // namespace

namespace {

/// The unit of a parameter by the tools' one rule (vehs/io/parameter_units.hpp); "-" for a name the
/// rule cannot read (a label never stops the report).
std::string unit_of(const std::string& name, const nlohmann::json& units) {
  try {
    return parameter_unit(name, units);
  } catch (const Error&) {
    return "-";
  }
}

/// The standard error of a model parameter: from the model's maps, or its covariance.
double parameter_se(const Model& m, const std::string& name, const std::map<std::string, double>& se, const std::string& key) {
  if (auto it = se.find(key); it != se.end()) return it->second;
  const auto i = m.covariance.index_of(name);
  return i < m.covariance.size() ? std::sqrt(std::max(0.0, m.covariance(i, i))) : std::nan("");
}

double measurement_sd_se(const LikelihoodFit& l) {
  const std::size_t n = l.parameters.size();
  for (std::size_t i = 0; i < n; ++i)
    if (l.parameters[i] == "measurement_sd" && l.covariance.size() == n * n) return std::sqrt(std::max(0.0, l.covariance[i * n + i]));
  return std::nan("");
}

ReportTable parameter_table(const Model& m, const nlohmann::json& units) {
  ReportTable t;
  t.caption = "Parameters of the diagnosed model (b2 = Σ coefficient · term; a22 likewise)";
  t.header = {"parameter", "value", "standard error", "unit"};
  for (const auto& tc : m.drift)
    t.rows.push_back({"drift[" + tc.term.name() + "]", g(tc.coef, 6),
                      g(parameter_se(m, "drift[" + tc.term.name() + "]", m.drift_stderr, tc.term.name()), 2),
                      unit_of("drift[" + tc.term.name() + "]", units)});
  for (const auto& tc : m.diffusion)
    t.rows.push_back({"diffusion[" + tc.term.name() + "]", g(tc.coef, 6),
                      g(parameter_se(m, "diffusion[" + tc.term.name() + "]", m.diffusion_stderr, tc.term.name()), 2),
                      unit_of("diffusion[" + tc.term.name() + "]", units)});
  for (const auto& e : m.effects)
    for (const auto& [k, v] : e.params)
      t.rows.push_back({e.name() + "." + k, g(v, 6), g(parameter_se(m, e.name() + "." + k, e.stderr_, k), 2),
                        unit_of(e.name() + "." + k, units)});
  if (m.fit && m.fit->likelihood && m.fit->likelihood->measurement_sd > 0)
    t.rows.push_back({"measurement_sd (sensor noise on x)", g(m.fit->likelihood->measurement_sd, 4),
                      g(measurement_sd_se(*m.fit->likelihood), 2), unit_text({1, 0, 0}, units)});
  return t;
}

/// The summary card: verdict, the next step, the parameter table and the fit to the measured x.
void add_top_card(Report& report, const diagnose::Result& r, const std::string& model_label, const Model* model,
                  const nlohmann::json& units, const std::string& next_command, const DrivenValidation* dv) {
  auto& s = report.section("Summary");
  s.id = "top-card";
  s.card = true;
  s.paragraphs.push_back("Verdict: " + std::string(r.adequate() ? "ADEQUATE" : "INADEQUATE") + " for \u201c" +
                         model_label + "\u201d (score " + g(r.score) + "; an adequate model scores about " +
                         g(r.score_expected_adequate, 2) + ", lower is better).");
  if (!next_command.empty()) {
    std::string names;
    for (const auto& e : r.recommended) names += (names.empty() ? "" : ", ") + e;
    s.paragraphs.push_back("Next step: add " + names + " (confirmed on held-out data). The identify-vehs config "
                           "beside this report, refit.json, fits the model with it on the same data; run:");
    s.code.push_back(next_command);
  } else {
    s.paragraphs.push_back(next_step(r, model));
  }
  if (dv && dv->available)
    s.paragraphs.push_back("Measured vs simulated (free run under the recorded input): fit " + g(dv->fit_percent, 3) +
                           " % (100 (1 − ‖x − x̂‖ / ‖x − mean x‖), as MATLAB's compare).");
  if (model) s.tables.push_back(parameter_table(*model, units));
}

/// Measured vs simulated and the residual–input cross-correlation (driven data).
void add_validation(Report& report, const DrivenValidation& dv, const nlohmann::json& units) {
  auto& s = report.section("Measured vs simulated under the recorded input");
  if (!dv.available) {
    s.paragraphs.push_back("Not shown: " + dv.note + ".");
    return;
  }
  auto axis = [&](const std::string& label, const std::string& what) { return with_unit(label, what, units); };
  std::string per;
  for (double f : dv.record_fit) per += (per.empty() ? "" : ", ") + g(f, 3) + " %";
  s.paragraphs.push_back("The model run without its process noise under each record's input from the record's measured "
                         "initial state, scored after the transient: fit " + g(dv.fit_percent, 3) + " % pooled (per record: " +
                         per + ")" + (dv.note.empty() ? "" : "; " + dv.note) + ". A stochastic model's free run "
                         "reproduces only the input-driven part of x, so 100 % is not expected.");
  Table mv({"t", "measured", "simulated"});
  for (std::size_t i = 0; i < dv.t.size(); ++i) mv.add_row({dv.t[i], dv.measured[i], dv.simulated[i]});
  report.add_figure(s, "measured_vs_simulated",
                    "Measured x (red) and the model's free run (blue) on the first record, after the transient; fit " +
                        g(dv.record_fit.front(), 3) + " %.",
                    mv,
                    "set grid\nset key below horizontal\nset xlabel " + gnuplot_quote(axis("t", "t")) + "\nset ylabel " +
                        gnuplot_quote(axis("x", "x")) + "\nset title " + gnuplot_quote("measured vs simulated: fit " + g(dv.fit_percent, 3) + " %") +
                        "\nplot 'measured_vs_simulated.csv' skip 1 using 1:2 with lines lw 1 lc rgb '#cb181d' title "
                        "'measured', '' skip 1 using 1:3 with lines lw 1.5 lc rgb '#2171b5' title 'simulated (free run)'");
  if (dv.lag.empty()) return;
  Table xc({"lag", "xcorr", "band"});
  for (std::size_t i = 0; i < dv.lag.size(); ++i) xc.add_row({dv.lag[i], dv.xcorr[i], dv.band[i]});
  s.paragraphs.push_back("Residual–input cross-correlation: largest |r| is " + g(dv.worst_ratio, 3) +
                         " times the 99 % band (at lag " + g(dv.worst_lag, 3) + "); " +
                         (dv.worst_ratio > 1 ? "outside the band: the residuals still depend on the input."
                                             : "inside the band: nothing of the input is left in the residuals."));
  report.add_figure(s, "residual_input_xcorr",
                    "Cross-correlation of the one-step residuals (acceleration minus the model's drift) with the input "
                    "u at lag τ (τ > 0: the input leads), with the 99 % band of independent series (Bartlett's "
                    "variance from both autocorrelations; MATLAB's resid). Bars outside the band: input dynamics the "
                    "model lacks.",
                    xc,
                    "set grid\nset key below horizontal\nset xlabel " + gnuplot_quote(axis("lag", "t")) +
                        "\nset ylabel 'correlation'\nset title 'residual-input cross-correlation'\nset style fill solid 0.6\n"
                        "plot 'residual_input_xcorr.csv' skip 1 using 1:2 with impulses lw 3 lc rgb '#2171b5' title "
                        "'r(residual, input)', '' skip 1 using 1:3 with lines dt 2 lc rgb 'black' title '99 % band', '' "
                        "skip 1 using 1:(-$3) with lines dt 2 lc rgb 'black' notitle");
}

}  // namespace

std::string next_step(const diagnose::Result& r, const Model* model) {
  if (r.adequate()) return "Next step: none needed: the model reproduces the data within their statistical errors.";
  if (r.confirmation.ran) {
    if (r.recommended.empty())
      return "Next step: no effect of the catalogue explains the misfit (" + r.conclusion.substr(r.conclusion.find("— ") + 4) +
             "); see 'Confirmation by held-out refits'.";
    std::string names, listed;
    for (const auto& e : r.recommended) {
      names += (names.empty() ? "" : ", ") + e;
      listed += (listed.empty() ? "\"" : ", \"") + e + "\"";
    }
    bool per_record = false;  // a recommended forcing refitted with one phase per record
    for (const auto& e : r.confirmation.effects)
      if (e.confirmed && e.effect == "harmonic_forcing") per_record = per_record || e.per_record_phase;
    const std::string them = r.recommended.size() > 1 ? "them" : "it";
    if (model)
      return "Next step: add " + names + ": merge " + refit_config(r, *model).dump() +
             " into the identify-vehs config that fitted the model and identify again (the model's terms as the "
             "libraries, no re-selection: the refit that confirmed " + them + " on held-out data; the diagnosis "
             "JSON's refit_config).";
    return "Next step: add " + names + " to the model's own terms and identify again (\"effects\": [" + listed + "]" +
           (per_record ? ", \"likelihood\": {\"per_record_phase\": true}" : "") +
           " with the model's terms as the libraries and no re-selection: the refit that confirmed " + them +
           " on held-out data).";
  }
  for (const auto& sp : r.suspects.ranked)
    if (sp.significant)
      return "Next step: add " + sp.effect + " to the identify-vehs config (merge " + suspect_add_fragment(sp, r.user_effects).dump() +
             ") and identify again.";
  return "Next step: no effect of the catalogue explains the misfit; the one-step map below shows where in (x, v) "
         "the model fails.";
}

void add_diagnosis_to_report(Report& report, const diagnose::Result& r, const std::string& model_label,
                             const std::vector<nlohmann::ordered_json>& history, const std::string& fingerprint,
                             const nlohmann::json& units, const std::vector<ReportLink>& versions, const Model* model,
                             const Dataset* data, const std::string& next_command) {
  auto axis = [&](const std::string& label, const std::string& what) { return with_unit(label, what, units); };
  std::optional<DrivenValidation> validation;
  if (model && data) validation = driven_validation(*model, *data);
  add_top_card(report, r, model_label, model, units, next_command, validation ? &*validation : nullptr);
  if (validation) add_validation(report, *validation, units);
  // ------------------------------------------------------------------ verdict
  {
    auto& s = report.section("Verdict: the components");
    std::ostringstream p;
    p << "Score " << g(r.score) << " (an adequate model scores about " << g(r.score_expected_adequate, 2)
      << " on these components; lower is better; comparable between models fitted to the same data). "
      << "A component fails when its p-value is below " << g(r.threshold, 3)
      << " (family-wise level " << g(r.threshold * static_cast<double>(std::max<std::size_t>(1, r.components.size())), 2)
      << ", Bonferroni over the available components).";
    s.paragraphs.push_back(p.str());
    s.paragraphs.push_back(
        "How it works: the data and, for every record, twins simulated from the model (same duration, "
        "sampling interval, initial state, drive and measurement process) go through the same "
        "statistics; each component compares them unit by unit (" + r.unit_kind +
        "), so estimator biases, transients and the sampling lens cancel. Size = max(0, chi2/dof - 1).");
    ReportTable t;
    t.caption = "Components";
    t.header = {"component", "what is compared", "p-value", "chi2 / dof", "size", "status"};
    for (std::size_t i = 0; i < r.components.size(); ++i) {
      const auto& c = r.components[i];
      const bool failed = c.test.available && c.test.p_value < r.threshold;
      t.rows.push_back({c.name, c.what, c.test.available ? g(c.test.p_value, 3) : "-",
                        c.test.available ? g(c.test.chi2, 4) + " / " + g(c.test.dof, 3) : "-",
                        c.test.available ? g(c.test.excess, 3) : "-",
                        !c.test.available ? "not available: " + c.test.note : failed ? "FAILED" : "ok"});
      if (failed) t.highlight.push_back(i);
    }
    s.tables.push_back(t);
    for (const auto& w : r.warnings) s.paragraphs.push_back("Warning: " + w);
    if (!versions.empty()) {  // (the links follow the paragraphs)
      s.paragraphs.push_back("The report of every model version diagnosed on these data:");
      s.links = versions;
    }
    Table bars({"minus_log10_p", "size"}, "component");
    for (const auto& c : r.components)
      if (c.test.available)
        bars.add_row(label_text(c.name), {std::min(-std::log10(std::max(c.test.p_value, 1e-300)), 300.0), c.test.excess});
    bars.write_csv(report.folder() + "/components.csv");
    std::ostringstream body;
    body << "set style fill solid 0.6\nset boxwidth 0.6\nset grid y\nset key below horizontal\nset ylabel '-log10 p'\nset logscale y\n"
         << "set yrange [0.01:*]\nset xtics rotate by -30\nset title 'components of the verdict'\n"
         << "plot 'components.csv' skip 1 using 0:($2 > 0.01 ? $2 : 0.01):xtic(1) with boxes lc rgb '#6baed6' "
         << "notitle, " << -std::log10(std::max(r.threshold, 1e-300))
         << " with lines dt 2 lc rgb 'black' title 'failure threshold'";
    report.add_figure(s, "components",
                      "Evidence against the model per component: -log10 of the p-value (bars, log scale). Above the "
                      "dashed line the component fails (p below alpha / components).",
                      body.str());
  }

  // ------------------------------------------------------------------ one-step map
  {
    auto& s = report.section(r.adequate() ? "One-step residuals over phase space"
                                          : "Where the model fails: one-step residuals over phase space");
    s.paragraphs.push_back("Lens: " + r.lens.describe() + ". Residuals r = (a - b2(x, v)) / sqrt(c a22(x, v)/h).");
    const OneStepMap& m = r.map;
    Table t({"x", "v", "z_mean", "z_log_variance", "z_kurtosis", "mean_data", "mean_twin", "var_data", "var_twin",
             "kurt_data", "kurt_twin", "rows_data", "rows_twin", "used"});
    for (const auto& b : m.bins)
      t.add_row({b.x, b.v, b.used ? b.z_mean : std::nan(""), b.used ? b.z_var : std::nan(""),
                 b.used ? b.z_kurt : std::nan(""), b.mean_data, b.mean_twin, b.var_data, b.var_twin, b.kurt_data,
                 b.kurt_twin, b.n_data, b.n_twin, b.used ? 1.0 : 0.0});
    t.write_csv(report.folder() + "/one_step_map.csv");
    const double wx = (m.x_hi - m.x_lo) / std::max(m.nx, 1), wv = (m.v_hi - m.v_lo) / std::max(m.nv, 1);
    auto map_body = [&](int col, const std::string& title) {
      std::ostringstream os;
      os << "set title " << gnuplot_quote(title) << "\nset xlabel " << gnuplot_quote(axis("x", "x"))
         << "\nset ylabel " << gnuplot_quote(axis("v (lens velocity)", "v")) << "\n" << kDiverging
         << "set cblabel 'z (clipped at ±5)'\nset xrange [" << m.x_lo << ":" << m.x_hi << "]\nset yrange [" << m.v_lo
         << ":" << m.v_hi << "]\nset size ratio 0.75\n"
         << "plot 'one_step_map.csv' skip 1 using 1:2:($14 > 0 ? ($" << col << " > 5 ? 5 : ($" << col
         << " < -5 ? -5 : $" << col << ")) : NaN) with image pixels notitle";
      return os.str();
    };
    (void)wx;
    (void)wv;
    report.add_figure(s, "one_step_mean",
                      "Residual MEAN, data minus twins, as a z-score per (x, v) bin (paired jackknife over units). "
                      "Red: the data's acceleration is larger than the model predicts there; blue: smaller. For an "
                      "adequate model the colours are pale noise (|z| rarely above 3). A band at v = 0 points to dry "
                      "friction, a pattern odd in x to asymmetric stiffness, the outer |x| to stops or stiffness. "
                      "Edge bins also hold the rows beyond the range; white: too few rows.",
                      map_body(3, "one-step residual mean: z of data - twins"));
    report.add_figure(s, "one_step_variance",
                      "Residual VARIANCE, z of log(var data / var twins) per bin. Red: the data are noisier than the "
                      "model's diffusion a22(x, v) says (e.g. noise growing with |v|: velocity-dependent noise); "
                      "blue: quieter.",
                      map_body(4, "one-step residual variance: z of log(data/twins)"));
    Table pv({"v", "mean_z2", "var_z2"});
    for (int j = 0; j < m.nv; ++j)
      pv.add_row({m.v_lo + (j + 0.5) * (m.v_hi - m.v_lo) / m.nv, m.v_profile_mean[static_cast<std::size_t>(j)],
                  m.v_profile_var[static_cast<std::size_t>(j)]});
    pv.write_csv(report.folder() + "/one_step_profile_v.csv");
    Table px({"x", "mean_z2", "var_z2"});
    for (int i = 0; i < m.nx; ++i)
      px.add_row({m.x_lo + (i + 0.5) * (m.x_hi - m.x_lo) / m.nx, m.x_profile_mean[static_cast<std::size_t>(i)],
                  m.x_profile_var[static_cast<std::size_t>(i)]});
    px.write_csv(report.folder() + "/one_step_profile_x.csv");
    report.add_figure(s, "one_step_profile",
                      "Where along v (left) and x (right) the misfit sits: mean z² of the residual mean and "
                      "log-variance over the bins of each column / row. About 1 (dashed) for an adequate model.",
                      "set multiplot layout 1,2\nset grid\nset key below\nset ylabel 'mean z^2'\n"
                      "set xlabel " + gnuplot_quote(axis("v", "v")) + "\nplot 'one_step_profile_v.csv' skip 1 using 1:2 with linespoints pt 7 title "
                      "'residual mean', '' skip 1 using 1:3 with linespoints pt 5 title 'residual variance', 1 "
                      "with lines dt 2 lc rgb 'black' notitle\nset xlabel " + gnuplot_quote(axis("x", "x")) + "\nplot 'one_step_profile_x.csv' skip 1 "
                      "using 1:2 with linespoints pt 7 title 'residual mean', '' skip 1 using 1:3 with linespoints "
                      "pt 5 title 'residual variance', 1 with lines dt 2 lc rgb 'black' notitle\nunset multiplot");
    ReportTable wt;
    wt.caption = "Bins with the largest |z| of the residual mean";
    wt.header = {"x", "v", "z mean", "mean data", "mean twins", "z log-variance", "rows (data)"};
    for (int b : m.worst) {
      const MapBin& mb = m.bins[static_cast<std::size_t>(b)];
      wt.rows.push_back({g(mb.x, 3), g(mb.v, 3), g(mb.z_mean, 3), g(mb.mean_data, 3), g(mb.mean_twin, 3),
                         g(mb.z_var, 3), g(mb.n_data, 6)});
      if (std::abs(mb.z_mean) > 4) wt.highlight.push_back(wt.rows.size() - 1);
    }
    s.tables.push_back(wt);
  }

  // ------------------------------------------------------------------ residual memory
  {
    auto& s = report.section("Residual memory and periodicity");
    curve_table(r.residual_acf, "lag", false, 1).write_csv(report.folder() + "/residual_acf.csv");
    report.add_figure(s, "residual_acf",
                      "Autocorrelation of the whitened residuals (lag in time units), data (points) vs twins (band). "
                      "The lens itself correlates neighbouring residuals (central kinematics: +1/4 at the stride), so "
                      "compare with the band, not with zero: data above the band at longer lags mean memory the model "
                      "lacks (coloured excitation, a hidden electrical state).",
                      band_plot("residual_acf.csv", "residual autocorrelation", axis("lag", "t"), "autocorrelation", false, false,
                                "", r.residual_acf.at.size()));
    curve_table(r.residual_psd, "frequency", false).write_csv(report.folder() + "/residual_psd.csv");
    report.add_figure(s, "residual_psd",
                      "Power spectrum of the whitened residuals (cycles per time unit), data vs twins. A line the band "
                      "lacks is periodic forcing; excess at low frequency is slow memory.",
                      band_plot("residual_psd.csv", "residual spectrum", axis("frequency", "f"),
                                axis("PSD of the whitened residuals", "t"), true, true, "", r.residual_psd.at.size()));
  }

  // ------------------------------------------------------------------ stationary statistics
  {
    auto& s = report.section("Stationary statistics: densities, power, wells");
    const bool fpk = !r.px.reference.empty();
    curve_table(r.px, "x", true).write_csv(report.folder() + "/px.csv");
    report.add_figure(s, "px",
                      "Displacement density p(x): data (points ± se from the spread over units), model twins (band "
                      "± 2 se)" + std::string(fpk ? ", and the stationary FPK density of the model (dashed; a "
                      "reference only: records that start out of equilibrium differ from it, twins do not)." : ".") +
                      " Hellinger distance data vs twins " + g(r.hellinger_px, 3) +
                      (r.hellinger_px_null >= 0 ? " (twin vs twin: " + g(r.hellinger_px_null, 3) + ")" : "") + ".",
                      band_plot("px.csv", "p(x)", axis("x", "x"), axis("density", "1/x"), false, false,
                                fpk ? ", \\\n  '' skip 1 using 1:6 with lines dt 2 lw 2 lc rgb 'black' title 'FPK (stationary)'"
                                    : "", r.px.at.size()));
    Table pxy({"x", "v", "p_data", "p_twin"});
    const double dx = (r.pxy_x_hi - r.pxy_x_lo) / std::max(r.pxy_nx, 1), dv = (r.pxy_v_hi - r.pxy_v_lo) / std::max(r.pxy_nv, 1);
    double pmax = 0.0;
    for (int i = 0; i < r.pxy_nx; ++i)
      for (int j = 0; j < r.pxy_nv; ++j) {
        const auto k = static_cast<std::size_t>(i * r.pxy_nv + j);
        pxy.add_row({r.pxy_x_lo + (i + 0.5) * dx, r.pxy_v_lo + (j + 0.5) * dv, r.pxy_data[k], r.pxy_twin[k]});
        pmax = std::max({pmax, r.pxy_data[k], r.pxy_twin[k]});
      }
    pxy.write_csv(report.folder() + "/pxy.csv");
    std::ostringstream body;
    body << "set multiplot layout 1,2\nset palette rgbformulae 33,13,10\nset cbrange [0:" << (pmax > 0 ? pmax : 1)
         << "]\nset xlabel " << gnuplot_quote(axis("x", "x")) << "\nset ylabel " << gnuplot_quote(axis("v", "v"))
         << "\nset xrange [" << r.pxy_x_lo << ":" << r.pxy_x_hi << "]\nset yrange ["
         << r.pxy_v_lo << ":" << r.pxy_v_hi << "]\nset title 'data'\nplot 'pxy.csv' skip 1 using 1:2:3 with image "
         << "pixels notitle\nset title 'model twins'\nplot 'pxy.csv' skip 1 using 1:2:4 with image pixels notitle\n"
         << "unset multiplot";
    report.add_figure(s, "pxy",
                      "Joint density p(x, v) of displacement and lens velocity: data (left) vs model twins (right), same "
                      "colour scale. Hellinger distance " + g(r.hellinger_pxy, 3) +
                          (r.hellinger_pxy_null >= 0 ? " (twin vs twin: " + g(r.hellinger_pxy_null, 3) + ")" : "") + ".",
                      body.str());
    ReportTable t;
    t.caption = "Stationary quantities: data vs model twins (paired z over units; without the parameter uncertainty)";
    t.header = {"quantity", "data", "model twins", "z", "FPK (stationary model)"};
    for (std::size_t i = 0; i < r.quantities.size(); ++i) {
      const auto& q = r.quantities[i];
      t.rows.push_back({q.name, pm(q.data, q.data_se), pm(q.twin, q.twin_se), g(q.z, 3), g(q.reference)});
      if (std::abs(q.z) > 3) t.highlight.push_back(i);
    }
    s.tables.push_back(t);
    Table qz({"z", "relative_difference", "relative_se"}, "quantity");
    for (const auto& q : r.quantities) {
      const bool ok = std::isfinite(q.z) && std::abs(q.twin) > 0;
      qz.add_row(label_text(q.name), {ok ? std::max(-20.0, std::min(20.0, q.z)) : 0.0,
                                      ok ? (q.data - q.twin) / std::abs(q.twin) : 0.0,
                                      ok ? std::hypot(q.data_se, q.twin_se) / std::abs(q.twin) : 0.0});
    }
    qz.write_csv(report.folder() + "/quantities.csv");
    report.add_figure(s, "quantities",
                      "Stationary quantities (power and wells components): paired z of data minus model twins per "
                      "quantity (bars, clipped at ±20); dashed: ±3. A mean power (E[v^2]) or well occupancy the model "
                      "does not reproduce stands out here.",
                      "set style fill solid 0.6\nset boxwidth 0.6\nset grid y\nset key below horizontal\nset ylabel 'z (data - twins)'\n"
                      "set xtics rotate by -30\nset title 'stationary quantities'\nplot 'quantities.csv' skip 1 using "
                      "0:2:xtic(1) with boxes lc rgb '#fd8d3c' notitle, 3 with lines dt 2 lc rgb 'black' title '|z| = 3', "
                      "-3 with lines dt 2 lc rgb 'black' notitle, 0 with lines lc rgb 'gray' notitle");
    s.paragraphs.push_back(
        "E[v^2] uses the lens velocity (a finite difference), so it is compared with the same quantity of the "
        "twins; the FPK column gives the model's stationary E[Y^2] (the mean harvested power is proportional to "
        "it). Wells come from the model's potential; a transition is counted when x enters the core (lower half) "
        "of another well. " + r.fpk_note);
  }

  // ------------------------------------------------------------------ time statistics
  {
    auto& s = report.section("Time statistics of x");
    curve_table(r.x_acf, "lag", false).write_csv(report.folder() + "/x_acf.csv");
    report.add_figure(s, "x_acf",
                      "Autocorrelation of x (lag in time units): data (points ± se over units) vs model twins (band ± 2 "
                      "se). Neighbouring lags are strongly correlated: read the shape, the test uses spectral bands.",
                      band_plot("x_acf.csv", "autocorrelation of x", axis("lag", "t"), "autocorrelation", false, false, "",
                                r.x_acf.at.size()));
    curve_table(r.x_psd, "frequency", false).write_csv(report.folder() + "/x_psd.csv");
    report.add_figure(s, "x_psd",
                      "Power spectrum of x (cycles per time unit; x block-averaged before the FFT, identically for both "
                      "sides): data vs model twins. The acf component compares log-spaced bands of it.",
                      band_plot("x_psd.csv", "power spectrum of x", axis("frequency", "f"), axis("PSD of x", "psd_x"), true,
                                true, "", r.x_psd.at.size()));
  }

  // ------------------------------------------------------------------ suspects
  // Ordered by what was claimed: the score tests on all the data (claimed first, then by z),
  // then the held-out suspects; held-out evidence that was set aside goes to its own section,
  // after the claims.
  {
    auto& s = report.section("Suspects: effects the model may be missing");
    if (!r.suspects.note.empty()) s.paragraphs.push_back(r.suspects.note);
    const bool aside = !r.suspects.set_aside.empty();
    if (!r.score_suspects.ranked.empty()) {
      const auto& ss = r.score_suspects;
      std::vector<const diagnose::ScoreSuspect*> order;
      for (const auto& sp : ss.ranked) order.push_back(&sp);
      std::stable_sort(order.begin(), order.end(), [](const auto* a, const auto* b) {
        return a->significant != b->significant ? a->significant : a->z > b->z;
      });
      s.paragraphs.push_back(
          "Likelihood score tests on all the data (" + g(static_cast<double>(ss.samples), 6) + " samples in " +
          std::to_string(ss.records) + " records): for each effect the model lacks, how much the likelihood of "
          "the model's filter rises when the effect's parameter leaves 0 (z = the normal quantile of p). 'under "
          "the model': how often the test claims the effect on data simulated from the model; 'power': how often "
          "on data from the model plus the fitted effect. Not claimed with a high power: the effect is absent; "
          "with a low power: too little data ('detectable': the size these data would reveal).");
      ReportTable t;
      t.caption = "Score-test suspects (likelihood, all data), claimed first";
      t.header = {"effect", "z", "p", "claimed", "under the model", "power", "fitted parameters", "detectable"};
      Table bars({"z", "claimed"}, "effect");
      for (const auto* sp : order) {
        t.rows.push_back({sp->effect, g(sp->z, 3), g(sp->p_value, 2), sp->significant ? "yes" : "no",
                          g(sp->null_claim_rate, 2), g(sp->power, 2), params_text(sp->params, sp->params_stderr),
                          sp->detectable});
        if (sp->significant) {
          t.highlight.push_back(t.rows.size() - 1);
          s.paragraphs.push_back("To fit " + sp->effect + " (" + sp->test + "), merge into the identify-vehs config: " + sp->add);
        }
        bars.add_row(label_text(sp->effect), {std::isfinite(sp->z) ? sp->z : 0.0, sp->significant ? 1.0 : 0.0});
      }
      s.tables.push_back(t);
      bars.write_csv(report.folder() + "/suspects.csv");
      report.add_figure(s, "suspects",
                        "Score-test z of every effect the model lacks, claimed effects first (red: claimed). An effect "
                        "is claimed when its p is below alpha over the tested effects.",
                        "set style fill solid 0.6\nset boxwidth 0.6\nset grid y\nset key below horizontal\nset ylabel 'z'\n"
                        "set xtics rotate by -30\nset title 'suspects (score tests, all data)'\nplot 'suspects.csv' skip 1 "
                        "using 0:($3 > 0 ? $2 : NaN):xtic(1) with boxes lc rgb '#cb181d' title 'claimed', '' skip 1 using "
                        "0:($3 > 0 ? NaN : $2) with boxes lc rgb '#6baed6' title 'not claimed', 0 with lines lc rgb 'gray' notitle");
    }
    if (!r.suspects.ranked.empty()) {
      auto& h = aside ? report.section("Set aside: held-out suspects (not a test on these data)") : s;
      if (aside) h.paragraphs.push_back("NOT A TEST ON THESE DATA: " + r.suspects.set_aside + ". Shown for reference; nothing is claimed from them.");
      std::vector<const diagnose::Suspect*> order;
      for (const auto& sp : r.suspects.ranked) order.push_back(&sp);
      std::stable_sort(order.begin(), order.end(), [](const auto* a, const auto* b) { return a->significant && !b->significant; });
      h.paragraphs.push_back(
          "Held-out suspects: each effect added to the model's terms, fitted by identify on the first part of every "
          "record and scored on the held-out rest (" + g(r.suspects.baseline_heldout_rows, 6) + " rows in " +
          std::to_string(r.suspects.blocks) + " blocks). Evidence = held-out log-likelihood gain in nats; z = gain / "
          "its standard error over blocks. Claimed only when z is large, the gain positive and the model inadequate.");
      ReportTable t;
      t.caption = aside ? "Held-out suspects, SET ASIDE" : "Held-out suspects, claimed first";
      t.header = {"effect", "evidence (nats)", "z", "claimed", "fitted parameters"};
      Table bars({"z", "evidence"}, "effect");
      for (const auto* sp : order) {
        t.rows.push_back({sp->effect, g(sp->evidence), g(sp->z, 3), aside ? "set aside" : sp->significant ? "yes" : "no",
                          params_text(sp->params, sp->params_stderr)});
        if (sp->significant && !aside) {
          t.highlight.push_back(t.rows.size() - 1);
          h.paragraphs.push_back("To fit " + sp->effect + ", merge into the identify-vehs config: " + suspect_add_fragment(*sp, r.user_effects).dump());
        }
        bars.add_row(label_text(sp->effect), {std::isfinite(sp->z) ? sp->z : 0.0, sp->evidence});
      }
      h.tables.push_back(t);
      bars.write_csv(report.folder() + "/suspects_heldout.csv");
      report.add_figure(h, "suspects_heldout",
                        std::string(aside ? "SET ASIDE, not a test on these data: " : "") +
                            "held-out z of every tested effect (bars); dashed: the significance threshold. Bars below "
                            "zero: the effect predicts held-out data worse than the model without it.",
                        std::string("set style fill solid 0.6\nset boxwidth 0.6\nset grid y\nset key below horizontal\nset ylabel 'held-out z'\n"
                                    "set xtics rotate by -30\nset title '") + (aside ? "held-out suspects (SET ASIDE)" : "held-out suspects") +
                            "'\nplot 'suspects_heldout.csv' skip 1 using 0:2:xtic(1) with boxes lc rgb '" + (aside ? "#bdbdbd" : "#6baed6") +
                            "' notitle, 3 with lines dt 2 lc rgb 'black' title 'threshold', 0 with lines lc rgb 'gray' notitle");
    }
    if (!r.suspects.untested.empty()) {
      ReportTable t;
      t.caption = "Effects not tested";
      t.header = {"effect", "why"};
      for (const auto& [name, why] : r.suspects.untested) t.rows.push_back({name, why});
      s.tables.push_back(t);
    }
  }

  // ------------------------------------------------------------------ confirmation
  if (r.confirmation.ran || !r.confirmation.note.empty()) {
    const auto& c = r.confirmation;
    auto& s = report.section("Confirmation by held-out refits");
    s.paragraphs.push_back("Conclusion: " + r.conclusion + ".");
    if (!c.note.empty()) s.paragraphs.push_back(c.note);
    if (c.ran) {
      s.paragraphs.push_back(
          "Every significant suspect (score tests and held-out) was refitted before being recommended: " + c.criterion +
          " (" + g(double(c.train_samples), 6) + " training samples, " + g(double(c.heldout_samples), 6) +
          " held out; nothing outside these data is used). Significant in a test but not confirmed by the refit "
          "means: the effect correlates with the misfit near the model, but the model refitted with it does not "
          "predict unseen data better.");
      ReportTable t;
      t.caption = "Suspects refitted and judged on held-out pieces (baseline: held-out log-likelihood " +
                  g(c.baseline_loglik) + (c.driven ? ", free-run RMSE " + g(c.baseline_rmse, 4) : std::string()) + ")";
      t.header = {"effect", "why a candidate", "confirmed", "held-out log-likelihood gain (nats)", "z"};
      if (c.driven) t.header.insert(t.header.end(), {"free-run RMSE with it", "z of the drop"});
      t.header.insert(t.header.end(), {"refitted parameters", "note"});
      for (std::size_t i = 0; i < c.effects.size(); ++i) {
        const auto& e = c.effects[i];
        std::vector<std::string> row{e.effect, e.evidence, e.confirmed ? "yes" : "no", g(e.loglik_gain), g(e.loglik_z, 3)};
        if (c.driven) row.insert(row.end(), {g(e.rmse_effect, 4), g(e.rmse_z, 3)});
        row.insert(row.end(), {params_text(e.params, e.params_stderr), e.error});
        t.rows.push_back(row);
        if (e.confirmed) t.highlight.push_back(i);
      }
      s.tables.push_back(t);
      const auto& rs = c.residuals;
      s.paragraphs.push_back("What the refitted baseline's held-out innovations show: " + rs.summary + ".");
      ReportTable f;
      f.caption = "Held-out innovations of the refitted baseline (z against white N(0, 1) innovations)";
      f.header = {"feature", "value", "z"};
      f.rows.push_back({"variance (1: calibrated)", g(rs.variance, 4), ""});
      f.rows.push_back({"lag-1 autocorrelation", g(rs.lag1, 3), g(rs.lag1_z, 3)});
      f.rows.push_back({"excess kurtosis", g(rs.excess_kurtosis, 3), g(rs.kurtosis_z, 3)});
      f.rows.push_back({"corr(z², " + rs.heteroscedastic_in + "²)", g(rs.heteroscedasticity, 3), g(rs.heteroscedasticity_z, 3)});
      if (std::isfinite(rs.input_z))
        f.rows.push_back({"largest corr(z, input) (lag " + std::to_string(rs.input_lag) + ")", g(rs.input_correlation, 3), g(rs.input_z, 3)});
      if (std::isfinite(rs.line_z)) f.rows.push_back({"largest spectral line (rad/time)", g(rs.line_frequency, 4), g(rs.line_z, 3)});
      s.tables.push_back(f);
    }
  }

  // ------------------------------------------------------------------ history
  {
    auto& s = report.section("Model history");
    Table h({"version", "score", "inadequate"}, "label");
    ReportTable t;
    t.caption = "Models diagnosed on these data (history file)";
    t.header = {"version", "label", "verdict", "score", "drift terms", "effects", "time"};
    for (const auto& e : history) {
      if (e.value("data_fingerprint", "") != fingerprint) continue;
      const double ver = e.value("version", 0.0);
      h.add_row(label_text(e.value("label", "")),
                {ver, e.value("score", 0.0), e.value("verdict", "") == "inadequate" ? 1.0 : 0.0});
      std::string terms, effects;
      if (e.contains("drift_terms"))
        for (const auto& x : e["drift_terms"]) terms += (terms.empty() ? "" : " ") + x.get<std::string>();
      if (e.contains("effects"))
        for (const auto& x : e["effects"]) effects += (effects.empty() ? "" : " ") + x.get<std::string>();
      t.rows.push_back({g(ver, 4), e.value("label", ""), e.value("verdict", ""), g(e.value("score", 0.0)), terms,
                        effects, e.value("time", "")});
    }
    h.write_csv(report.folder() + "/history.csv");
    report.add_figure(s, "history",
                      "Score of every model version diagnosed on these same data (lower is better; red: inadequate). "
                      "Adding a missing effect should bring the score down toward the level of an adequate model "
                      "(dashed: the score an adequate model reaches, about " + g(r.score_expected_adequate, 2) + ").",
                      "set grid\nset xlabel 'model version'\nset ylabel 'score'\nset key below horizontal\nset offsets "
                      "0.3, 0.3, 0, 0\nset xtics 1\nset yrange [0:*]\nplot 'history.csv' skip 1 using 2:3 with linespoints "
                      "pt 7 ps 1.2 lc rgb '#2171b5' title 'score', '' skip 1 using 2:($4 > 0 ? $3 : NaN) with points "
                      "pt 7 ps 1.6 lc rgb '#cb181d' title 'inadequate', " + g(r.score_expected_adequate, 4) +
                      " with lines dt 2 lw 2 lc rgb '#238b45' title 'adequate (about " + g(r.score_expected_adequate, 2) +
                      ")', '' skip 1 using 2:3:1 with labels offset 0,1 font ',9' notitle");
    s.tables.push_back(t);
  }

  // ------------------------------------------------------------------ settings
  {
    auto& s = report.section("Settings and provenance");
    ReportTable t;
    t.caption = "How the comparison was made";
    t.header = {"item", "value"};
    t.rows.push_back({"records / units", std::to_string(r.records) + " / " + std::to_string(r.units) + " (" + r.unit_kind + ")"});
    t.rows.push_back({"samples / lens rows", std::to_string(r.samples) + " / " + std::to_string(r.rows)});
    const std::string data_verdict = verdict_text(r.sampling.data_verdict);
    const std::string model_verdict = verdict_text(r.sampling.model_verdict);
    t.rows.push_back({"sampling of the data", data_verdict.empty() ? "-" : data_verdict});
    t.rows.push_back({"model file says", model_verdict.empty() ? "-" : model_verdict + " (" + estimator_text(r.sampling.model_estimator) + ")"});
    t.rows.push_back({"lens", r.lens.describe()});
    t.rows.push_back({"twins", std::to_string(r.sampling.replicates) + " per record, " + enum_to_string(sim::kSchemeNames, r.sampling.twin_scheme) + " with " +
                                   std::to_string(r.sampling.twin_substeps) + " substeps per sample" +
                                   (r.sampling.sensor_noise_sd > 0 ? ", sensor noise sd " + g(r.sampling.sensor_noise_sd) : "")});
    t.rows.push_back({"parameter uncertainty", r.parameter_draws > 0 ? std::to_string(r.parameter_draws) + " refits on " +
                                                                           std::to_string(r.parameter_fit_samples) + " samples each"
                                                                     : "not propagated"});
    double total = 0.0;
    for (const auto& [stage, seconds] : r.timings)
      if (stage == "total") total = seconds;
    t.rows.push_back({"run time", g(total, 3) + " s"});
    s.tables.push_back(t);
  }
}

}  // namespace vehs::tools
