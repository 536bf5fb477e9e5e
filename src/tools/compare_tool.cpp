#include "tools/compare_tool.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/parameters.hpp"
#include "tools/file_kind.hpp"
#include "tools/table.hpp"
#include "vehs/io/json_file.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/io/parameter_units.hpp"

namespace vehs::tools {

namespace {

ConfigSchema make_schema() {
  return {"vehs-compare",
          "Prints a table of true / reference / learned model parameters (beta, k_i, 2D, 2Q, ...) "
          "with the learned model's standard errors, and the stationary response E[X^2], E[Y^2] "
          "from fpk-stationary next to a Monte Carlo estimate.",
          {{"learned", "path", "model file written by identify-vehs", ""},
           {"truth", "path", "model file of the true parameters (deviation columns use it)", "", true},
           {"reported", "path", "model file of the values a paper reports", "", true},
           {"reported_label", "string", "column title for `reported`", "\"paper\""},
           {"fpk", "path", "statistics JSON written by fpk-stationary", "", true},
           {"monte_carlo", "path", "statistics JSON of simulate-vehs (with stderr)", "", true},
           {"output", "path", "also write the parameter table as CSV here (with each parameter's unit)", "", true}},
          "dev/se, rel.err and the FPK - Monte Carlo difference show \"overflow\" where the ratio exceeds the "
          "largest double (a standard error or true value near zero).\n"
          "Example: vehs-compare data/paper/compare.json"};
}

/// The marker printed for a ratio beyond the largest double (documented in --help).
constexpr const char* kOverflow = "overflow";

double stat(const nlohmann::json& j, const std::string& key, const std::string& file) {
  if (!j.contains(key) || !j[key].is_number()) throw Error(file + ": no number '" + key + "'");
  const double v = j[key].get<double>();
  if (!std::isfinite(v)) throw Error(file + ": '" + key + "' is not finite");
  return v;
}

/// A ratio formatted by `format`, or kOverflow where it is not a finite double (a standard error
/// or a true value near the smallest double: 1e308 / 1e-300).
std::string ratio_text(double ratio, const char* format) {
  if (!std::isfinite(ratio)) return kOverflow;
  char text[64];
  std::snprintf(text, sizeof text, format, ratio);
  return text;
}

bool same_terms(const TermList& a, const TermList& b) {
  auto nonzero = [](const TermList& t) {
    std::map<std::string, double> m;
    for (const auto& tc : t)
      if (tc.coef != 0.0) m[tc.term.name()] = tc.coef;
    return m;
  };
  const auto ma = nonzero(a), mb = nonzero(b);
  if (ma.size() != mb.size()) return false;
  for (const auto& [name, coef] : ma) {
    const auto it = mb.find(name);
    if (it == mb.end() || std::abs(it->second - coef) > 1e-12 * std::max(std::abs(coef), std::abs(it->second)))
      return false;
  }
  return true;
}

bool same_model(const Model& a, const Model& b) {
  return same_terms(a.drift, b.drift) && same_terms(a.diffusion, b.diffusion) && a.effects.size() == b.effects.size();
}

// Which of the compared models the statistics file `path` was computed for ("learned", "true",
// the reported label); an error when it names none of them or records no model (a file of another
// model would otherwise be printed as the learned model's response).
std::string owner_of(const nlohmann::json& stats, const std::string& path, const Config& c,
                     const std::vector<std::pair<std::string, const Model*>>& models) {
  if (!stats.is_object() || !stats.contains("model"))
    throw Error(path + ": records no 'model', so it cannot be checked against " + c.string("learned") +
                " (rewrite it with the current fpk-stationary / simulate-vehs)");
  const Model m = model_from_json(stats["model"], path + ": 'model'");
  for (const auto& [label, candidate] : models)
    if (candidate && same_model(m, *candidate)) return label;
  throw Error(path + ": was computed for another model than 'learned' " + c.string("learned") +
              (models.size() > 1 ? " (and than the truth and reported models)" : ""));
}

using Compared = std::vector<std::pair<std::string, const Model*>>;

struct Statistics {
  nlohmann::json values;
  std::string owner;  ///< the label of the compared model it was computed for
};

/// The statistics file named by the config key `key` ("fpk", "monte_carlo"), refused unless the
/// expected tool wrote it for one of `models` and its moments are numbers (checked before
/// anything is printed).
Statistics read_statistics(const Config& c, const std::string& key, FileKind expected, const Compared& models) {
  const std::string path = c.path(key);
  nlohmann::json j = read_json_file(path, expected == FileKind::FpkResult ? "FPK result" : "Monte Carlo statistics");
  if (const FileKind kind = file_kind(j); kind != expected)
    c.fail(key, "names " + path + ", " + describe(kind) + "; it takes " + describe(expected) + " (the file of its " +
                    (expected == FileKind::FpkResult ? "'output'" : "'statistics.output'") + ")");
  std::string owner = owner_of(j, path, c, models);
  for (const char* k : {"E[X^2]", "E[Y^2]", "E[XY]"}) {
    (void)stat(j, k, path);
    if (j.contains("stderr") && j["stderr"].is_object() && j["stderr"].contains(k)) (void)stat(j["stderr"], k, path);
  }
  return {std::move(j), std::move(owner)};
}

/// The model file named by the config key `key`; a statistics file given instead is named as such.
ModelFile read_model(const Config& c, const std::string& key) {
  const std::string path = c.path(key);
  try {
    return read_model_file(path);
  } catch (const Error&) {  // (only a file that failed is read again, to say what it is)
    FileKind kind = FileKind::Other;
    try {
      kind = file_kind(read_json_file(path, "model"));
    } catch (const Error&) {
    }
    if (kind == FileKind::FpkResult || kind == FileKind::MonteCarloStatistics)
      c.fail(key, "names " + path + ", " + describe(kind) + "; it takes " + describe(FileKind::Model));
    throw;
  }
}

/// The model files' `units` sections must agree where both state them: the coefficients of a
/// model in m and one in mm differ by powers of 1000 (a new user's comparison printed k3 off by
/// +99 386 066 % with exit 0).
void require_same_units(const std::string& a, const ModelFile& fa, const std::string& b, const ModelFile& fb) {
  const auto units = [](const ModelFile& f) {
    return f.sections.contains("units") && f.sections["units"].is_object() ? f.sections["units"]
                                                                         : nlohmann::ordered_json::object();
  };
  const nlohmann::ordered_json ua = units(fa), ub = units(fb);
  for (const auto& [key, value] : ua.items())
    if (ub.contains(key) && ub[key] != value)
      throw Error(a + " states units." + key + " = " + value.dump() + " but " + b + " states " + ub[key].dump() +
                  ": compare models fitted in the same units (refit one with the other's data units)");
}

}  // namespace

const ConfigSchema& compare_schema() {
  static const ConfigSchema schema = make_schema();
  return schema;
}

int run_compare(Config& c, const AppOptions&) {
  const ModelFile learned_file = read_model(c, "learned");
  auto checked_model = [&](const std::string& key) {  // a model the library would refuse is no table entry
    const std::string path = c.path(key);
    ModelFile f = key == "learned" ? learned_file : read_model(c, key);
    validate_model(f.model, path);
    if (key != "learned") require_same_units(c.string("learned"), learned_file, path, f);
    return f.model;
  };
  const Model learned = checked_model("learned");
  std::optional<Model> truth, reported;
  if (c.has("truth")) truth = checked_model("truth");
  if (c.has("reported")) reported = checked_model("reported");
  const std::string rlabel = c.string_or("reported_label", "paper");
  // every input's kind and model before the first line of output
  const Compared models = {
      {"learned", &learned}, {"true", truth ? &*truth : nullptr}, {rlabel, reported ? &*reported : nullptr}};
  Statistics fpk_file, mc_file;
  if (c.has("fpk")) fpk_file = read_statistics(c, "fpk", FileKind::FpkResult, {models[0]});  // of the learned model
  if (c.has("monte_carlo")) mc_file = read_statistics(c, "monte_carlo", FileKind::MonteCarloStatistics, models);
  const nlohmann::json &fpk = fpk_file.values, &mc = mc_file.values;
  const std::string& mc_owner = mc_file.owner;

  // union of parameter names, in the learned model's order, then the others
  std::vector<std::string> names;
  std::set<std::string> seen;
  auto collect = [&](const Model& m) {
    for (const auto& p : physical_parameters(m))
      if (seen.insert(p.name).second) names.push_back(p.name);
  };
  if (truth) collect(*truth);
  collect(learned);
  if (reported) collect(*reported);
  std::map<std::string, PhysicalParameter> lp;
  for (const auto& p : physical_parameters(learned)) lp[p.name] = p;
  // units (vehs/io/parameter_units.hpp): printed when the learned model file states them
  const nlohmann::json units = units_of(learned_file.sections);
  const bool print_units = !units.empty();

  int name_width = 16;  // the longest name (coulomb_friction.mu) widens the first column
  for (const auto& n : names) name_width = std::max(name_width, static_cast<int>(n.size()));
  std::printf("%-*s %11s %11s %24s %10s %9s%s\n", name_width, "parameter", truth ? "true" : "", reported ? rlabel.c_str() : "",
              "learned +- stderr", truth ? "dev/se" : "", truth ? "rel.err" : "", print_units ? "  unit" : "");
  Table table({"true", "reported", "learned", "stderr"}, "parameter");
  table.text_column = "unit";
  for (const auto& n : names) {
    const double tv = truth ? get_parameter(*truth, n) : NAN;
    const double rv = reported ? get_parameter(*reported, n) : NAN;
    const bool has = lp.count(n) > 0;
    const double lv = has ? lp[n].value : 0.0;
    const double se = has && lp[n].stderr_ ? *lp[n].stderr_ : NAN;
    char learned_text[64];
    if (has && se > 0)
      std::snprintf(learned_text, sizeof learned_text, "%.6g +- %.2g", lv, se);
    else if (has)
      std::snprintf(learned_text, sizeof learned_text, "%.6g", lv);
    else
      std::snprintf(learned_text, sizeof learned_text, "(not selected)");
    std::string dev, rel;
    if (truth && has && se > 0) dev = ratio_text((lv - tv) / se, "%+.2f");
    if (truth && tv != 0.0) rel = ratio_text(100.0 * (lv - tv) / std::abs(tv), "%+.2f%%");
    char tvs[32] = "", rvs[32] = "";
    if (truth) std::snprintf(tvs, sizeof tvs, "%.6g", tv);
    if (reported) std::snprintf(rvs, sizeof rvs, "%.6g", rv);
    const std::string unit = parameter_unit(n, units);
    std::printf("%-*s %11s %11s %24s %10s %9s%s\n", name_width, n.c_str(), tvs, rvs, learned_text, dev.c_str(), rel.c_str(),
                print_units ? ("  " + unit).c_str() : "");
    table.add_text_row(n, {tv, rv, has ? lv : NAN, se}, unit);
  }
  if (truth) {
    auto support = [](const TermList& terms) {
      std::set<std::string> s;
      for (const auto& t : terms)
        if (t.coef != 0.0) s.insert(t.term.name());
      return s;
    };
    auto joined = [](const std::set<std::string>& s) {
      std::string r;
      for (const auto& n : s) r += (r.empty() ? "" : ", ") + n;
      return r;
    };
    const bool same_drift = support(learned.drift) == support(truth->drift);
    const bool same_diffusion = support(learned.diffusion) == support(truth->diffusion);
    std::printf("\nselected drift terms:     %s  (%s)\n", joined(support(learned.drift)).c_str(),
                same_drift ? "exactly the true ones" : "differs from the truth");
    std::printf("selected diffusion terms: %s  (%s)\n", joined(support(learned.diffusion)).c_str(),
                same_diffusion ? "exactly the true ones" : "differs from the truth");
  }
  if (c.has("fpk") || c.has("monte_carlo")) {
    std::printf("\nStationary response of the learned model (mean power E(P) is proportional to E[Y^2]):\n");
    for (const char* key : {"E[X^2]", "E[Y^2]", "E[XY]"}) {
      std::printf("  %-7s", key);
      if (c.has("fpk")) std::printf("  FPK %.6f", stat(fpk, key, c.string("fpk")));
      if (c.has("monte_carlo")) {
        const double v = stat(mc, key, c.string("monte_carlo"));
        const bool has_se = mc.contains("stderr") && mc["stderr"].is_object() && mc["stderr"].contains(key);
        const double se = has_se ? stat(mc["stderr"], key, c.string("monte_carlo")) : 0.0;
        const std::string of = mc_owner == "learned" ? "" : " (of the " + mc_owner + " model)";
        if (se > 0)
          std::printf("   Monte Carlo%s %.6f +- %.6f", of.c_str(), v, se);
        else
          std::printf("   Monte Carlo%s %.6f (no standard error)", of.c_str(), v);
        if (c.has("fpk") && se > 0 && mc_owner == "learned")
          std::printf("   (difference %s se)", ratio_text((stat(fpk, key, c.string("fpk")) - v) / se, "%+.2f").c_str());
      }
      std::printf("\n");
    }
  }
  if (c.has("output")) table.write_csv(c.path("output"));
  return 0;
}

}  // namespace vehs::tools
