// Benchmarks of the likelihood refinement (issue 12). Run them all with bench/likelihood.sh,
// which writes bench/results/likelihood*.txt; each subcommand prints its own table:
//
//   bench_likelihood synthetic MODEL DT NOISE SEEDS T_RECORD RECORDS [B]
//        MODEL bistable | paper; NOISE 0 or 0.02 (share of std(x)); per seed: identify (auto,
//        the "before") and the likelihood (start: identify's full-library fit, selection by
//        BIC; B > 0: bias correction from B simulated data sets): exact support, max |z|, max
//        relative error, coverage of the 95 % intervals; seeds FIRST_SEED … (environment, 0)
//   bench_likelihood score MODEL DT NOISE SEEDS T_RECORD RECORDS [PF_RECORDS PARTICLES]
//        the filter's score at the truth over seeds (its bias), variants that separate causes
//   bench_likelihood innovations MODEL DT NOISE SEEDS T_RECORD RECORDS
//        standardised one-step innovations at the truth, binned by the predicted |x|
//   bench_likelihood driven SEEDS           driven Duffing, 10 samples per period, free run on a
//                                           fresh input against the noise floor
//   bench_likelihood effects SEEDS [FIRST [EFFECT]]  electromechanical, coloured, per-record
//                                           harmonic (seeds FIRST …; only EFFECT when given)
//   bench_likelihood speed [MAX]            10^5, 3·10^5, 10^6 samples (up to MAX): refine wall time
//   bench_likelihood silverbox              the standard split, before/after, interpolations
//   bench_likelihood gaussian               filter vs particle-filter log-likelihood
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/likelihood/free_run.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/likelihood/score_test.hpp"
#include "vehs/likelihood/signals.hpp"
#include "vehs/sim/simulate.hpp"

using namespace vehs;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

Model parse(const char* j) { return model_from_json(nlohmann::json::parse(j), "bench"); }

Model bistable() { return parse(R"({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.04}})"); }
Model paper() {
  return parse(R"({"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
                   "diffusion": {"1": 0.02, "x^2": 0.01}})");
}

Dataset simulate(const Model& m, double dt, int records, double T, std::uint64_t seed, double noise,
                 const std::vector<double>* drive = nullptr, double x_span = 1.5) {
  sim::SimulationOptions o;
  o.dt = dt;
  // VEHS_GEN_SUBSTEPS: the generator's Taylor 1.5 steps per interval (default 40). At 16x the
  // paper's model at dt 0.236, 40 steps bias the data by ~0.45 SE in the x^3...x^9 direction
  // (the walls' stiffness, h*|f'| up to 0.5); 160 steps do not (bench_likelihood spread)
  o.substeps = std::getenv("VEHS_GEN_SUBSTEPS") ? std::atoi(std::getenv("VEHS_GEN_SUBSTEPS")) : 40;
  o.records = records;
  o.samples = std::size_t(std::llround(T / dt));
  o.seed = seed;
  o.scheme = sim::Scheme::Taylor15;
  o.sensor_noise = noise;
  o.record_y = false;
  o.burn_in = drive ? 0.0 : 50.0;
  o.x0.lo = -x_span;
  o.x0.hi = x_span;
  if (drive) o.drive = *drive;
  return sim::simulate(m, o);
}

double sd_of(const vehs::Column& v) {
  double m = 0, s = 0;
  for (double x : v) m += x;
  m /= double(v.size());
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / double(v.size() - 1));
}

std::string support_of(const Model& m) {
  std::string s;
  for (const auto& tc : m.drift)
    if (tc.coef != 0.0) s += (s.empty() ? "" : ",") + tc.term.name();
  s += " | ";
  for (const auto& tc : m.diffusion)
    if (tc.coef != 0.0) s += tc.term.name() + ",";
  return s;
}

bool same_support(const Model& a, const Model& b) { return support_of(a) == support_of(b); }

struct Score {
  double max_z = 0, max_rel = 0;
  int covered = 0, total = 0;
};
Score score(const likelihood::Result& r, const Model& truth, double noise) {
  Score s;
  auto one = [&](const std::string& name, double v) {
    const int i = r.find(name);
    if (i < 0) {
      s.max_z = INFINITY;
      s.max_rel = INFINITY;
      ++s.total;
      return;
    }
    const double est = r.values[std::size_t(i)], se = r.stderrs[std::size_t(i)];
    const double z = std::abs(est - v) / se;
    s.max_z = std::max(s.max_z, z);
    s.max_rel = std::max(s.max_rel, std::abs(est - v) / std::abs(v));
    s.covered += z <= 1.959964 ? 1 : 0;
    ++s.total;
  };
  for (const auto& tc : truth.drift) one("drift[" + tc.term.name() + "]", tc.coef);
  for (const auto& tc : truth.diffusion) one("diffusion[" + tc.term.name() + "]", tc.coef);
  if (noise > 0) one("measurement_sd", noise);
  return s;
}

double max_rel_moment(const Model& m, const Model& truth) {
  double worst = 0;
  for (const auto& tc : truth.drift) worst = std::max(worst, std::abs(coefficient(m.drift, tc.term) - tc.coef) / std::abs(tc.coef));
  for (const auto& tc : truth.diffusion)
    worst = std::max(worst, std::abs(coefficient(m.diffusion, tc.term) - tc.coef) / std::abs(tc.coef));
  return worst;
}

/// Signed z and signed relative error of one parameter over the seeds (bias vs tail).
using SignedErrors = std::map<std::string, std::vector<std::pair<double, double>>>;

void record_signed(SignedErrors& e, const likelihood::Result& r, const std::string& name, double truth) {
  const int i = r.find(name);
  if (i < 0) return;
  const double diff = r.values[std::size_t(i)] - truth;
  e[name].push_back({diff / r.stderrs[std::size_t(i)], diff / std::abs(truth)});
}

/// Quantile p of χ² with k degrees of freedom (Wilson–Hilferty; within 1 % of the exact
/// quantile for k ≥ 5 at p = 0.025 and 0.975).
double chi2_quantile(double k, double p) {
  const double z = p < 0.5 ? -1.959964 : 1.959964;  // (only p = 0.025, 0.975 are used)
  const double c = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - c + z * std::sqrt(c), 3.0);
}

/// One line per parameter: mean z, sd of z with its 95 % interval (calibrated SEs: sd 1; the
/// interval from χ²_{n−1} for normal z), mean relative error ± its SE over the seeds, coverage.
void print_bias(const std::string& label, const SignedErrors& params) {
  for (const auto& [name, list] : params) {
    const double n = double(list.size());
    double mz = 0, mr = 0, sz = 0, sr = 0;
    int cover = 0;
    for (const auto& [z, r] : list) mz += z / n, mr += r / n, cover += std::abs(z) <= 1.959964;
    for (const auto& [z, r] : list) sz += (z - mz) * (z - mz) / (n - 1), sr += (r - mr) * (r - mr) / (n - 1);
    const bool interval = n >= 6;  // (the approximation needs ≥ 5 degrees of freedom)
    const double lo = interval ? std::sqrt(sz * (n - 1) / chi2_quantile(n - 1, 0.975)) : NAN;
    const double hi = interval ? std::sqrt(sz * (n - 1) / chi2_quantile(n - 1, 0.025)) : NAN;
    std::printf("  %-28s %-26s mean z %+6.2f (+-%.2f) sd z %5.2f [%4.2f, %4.2f]  mean rel.err %+7.2f %% +- %5.2f %%  "
                "cover %d/%d\n",
                label.c_str(), name.c_str(), mz, 1 / std::sqrt(n), std::sqrt(sz), lo, hi, 100 * mr,
                100 * std::sqrt(sr / n), cover, int(n));
  }
}

/// `r` with the standard errors of another covariance choice (VEHS_SECOND_COVARIANCE): the
/// estimate's support refitted without selection or correction from `r` (the same maximum),
/// its SEs × √(1 + 1/B) when `r` was bias-corrected; the values stay r's.
likelihood::Result with_other_stderrs(const likelihood::Result& r, const Dataset& d, likelihood::RefineOptions o,
                                      const char* covariance, likelihood::Result* maximum = nullptr) {
  const int B = r.summary.bias_correction_datasets;
  o.covariance = enum_from_string(likelihood::kCovarianceNames, covariance, "VEHS_SECOND_COVARIANCE");
  o.select = false;
  o.bias_correction_datasets = 0;
  o.estimate_measurement_noise = r.find("measurement_sd") >= 0;
  o.warm_start_samples = std::size_t(-1);  // (starts at the maximum: no warm start)
  o.log = {};
  const likelihood::Result r2 = likelihood::refine(r.model, d, o);
  if (maximum) *maximum = r2;  // the uncorrected maximum with its own SEs
  likelihood::Result out = r;
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    const int j = r2.find(r.parameters[i].name);
    out.stderrs[i] = j < 0 ? NAN : r2.stderrs[std::size_t(j)] * std::sqrt(B > 0 ? 1.0 + 1.0 / B : 1.0);
  }
  out.summary.covariance = r2.summary.covariance;
  return out;
}

std::vector<Term> terms(std::initializer_list<const char*> names) {
  std::vector<Term> t;
  for (auto* n : names) t.push_back(Term::parse(n));
  return t;
}

int synthetic(const std::string& which, double dt, double noise_share, int seeds, double T, int records, int bias_sets) {
  const Model truth = which == "paper" ? paper() : bistable();
  identify::Options io;
  if (which == "paper") {
    io.drift_library = terms({"x", "x^2", "x^3", "x^5", "x^7", "x^9", "y", "x^2*y"});
    io.diffusion_library = terms({"1", "x^2"});
  } else {
    io.drift_library = terms({"1", "x", "x^2", "x^3", "x^5", "y", "x^2*y"});
    io.diffusion_library = terms({"1", "x^2"});
  }
  std::printf("# synthetic %s dt %.3f noise %.2f*sd(x), %d records x %.0f time units, generator substeps %s, library %zu drift + %zu diffusion terms%s\n",
              which.c_str(), dt, noise_share, records, T, std::getenv("VEHS_GEN_SUBSTEPS") ? std::getenv("VEHS_GEN_SUBSTEPS") : "40",
              io.drift_library.size(), io.diffusion_library.size(),
              bias_sets > 0 ? (", bias correction from " + std::to_string(bias_sets) + " simulated data sets").c_str() : "");
  std::printf("%-5s %-8s | %-6s %8s %-40s | %-6s %7s %7s %6s %7s %7s\n", "seed", "samples", "before", "rel.err", "before support",
              "exact", "max|z|", "rel.err", "cover", "seconds", "cpu");
  int exact = 0, within = 0, covered = 0, total = 0, before_exact = 0;
  SignedErrors signed_errors, second_errors, uncorrected_errors;
  const int first = std::getenv("FIRST_SEED") ? std::atoi(std::getenv("FIRST_SEED")) : 0;  // seeds FIRST …
  // VEHS_SECOND_COVARIANCE=sandwich|fisher|observed: z also with that choice's SEs (same estimates)
  const char* second = std::getenv("VEHS_SECOND_COVARIANCE");
  std::string second_method;
  std::size_t fitted = 0;  // seeds recorded
  for (int s = first; s < first + seeds; ++s) {
    const std::uint64_t seed = 1000 + std::uint64_t(s);
    const double sd = sd_of(simulate(truth, dt, 2, T, seed, 0.0).x);
    const double noise = noise_share * sd;
    const Dataset d = simulate(truth, dt, records, T, seed, noise);
    identify::Result before = identify::identify(d, io);
    identify::Options full = io;
    full.sparsity = identify::Sparsity::None;
    const identify::Result start = identify::identify(d, full);
    likelihood::RefineOptions o;
    o.select = true;
    o.estimate_measurement_noise = true;
    o.bias_correction_datasets = bias_sets;
    o.bias_correction_seed = 77000 + 100 * std::uint64_t(s);
    const bool verbose = std::getenv("VEHS_PROGRESS") != nullptr;
    if (verbose) o.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    likelihood::Result r;
    try {
      r = likelihood::refine({start.model, 0.0, {}}, d, o);
    } catch (const Error& e) {
      std::printf("%-5d error: %s\n", s, e.what());
      continue;
    }
    const double wall = seconds_since(t0), cpu = cpu_seconds() - c0;
    if (verbose)
      for (std::size_t i = 0; i < r.parameters.size(); ++i)
        std::fprintf(stderr, "  %-18s %12.6g +- %10.3g\n", r.parameters[i].name.c_str(), r.values[i], r.stderrs[i]);
    const bool ok_support = same_support(r.model.model, truth) && ((noise > 0) == (r.find("measurement_sd") >= 0));
    const Score sc = score(r, truth, noise);
    for (const auto& tc : truth.drift) record_signed(signed_errors, r, "drift[" + tc.term.name() + "]", tc.coef);
    for (const auto& tc : truth.diffusion) record_signed(signed_errors, r, "diffusion[" + tc.term.name() + "]", tc.coef);
    if (noise > 0) record_signed(signed_errors, r, "measurement_sd", noise);
    if (second) {
      likelihood::Result r_max;
      const likelihood::Result r2 = with_other_stderrs(r, d, o, second, &r_max);
      second_method = r2.summary.covariance;
      if (bias_sets > 0) {  // the maximum before the bias correction, with its own SEs: "zu"
        for (const auto& tc : truth.drift) record_signed(uncorrected_errors, r_max, "drift[" + tc.term.name() + "]", tc.coef);
        for (const auto& tc : truth.diffusion)
          record_signed(uncorrected_errors, r_max, "diffusion[" + tc.term.name() + "]", tc.coef);
      }
      for (const auto& tc : truth.drift) record_signed(second_errors, r2, "drift[" + tc.term.name() + "]", tc.coef);
      for (const auto& tc : truth.diffusion) record_signed(second_errors, r2, "diffusion[" + tc.term.name() + "]", tc.coef);
      if (noise > 0) record_signed(second_errors, r2, "measurement_sd", noise);
    }
    ++fitted;
    if (verbose)  // every seed's z (runs stopped early can still be summarised)
      for (const auto* e : {&signed_errors, &second_errors, &uncorrected_errors})
        for (const auto& [name, list] : *e)
          if (list.size() == fitted)
            std::fprintf(stderr, "z%s seed %d %s %+.4f rel %+.5f\n",
                         e == &signed_errors ? "" : e == &second_errors ? "2" : "u", s, name.c_str(),
                         list.back().first, list.back().second);
    exact += ok_support;
    before_exact += same_support(before.model, truth);
    within += sc.max_z <= 3.0 && sc.max_rel <= 0.05;
    covered += sc.covered;
    total += sc.total;
    std::printf("%-5d %-8zu | %-6s %7.1f%% %-40s | %-6s %7.2f %6.1f%% %3d/%-2d %7.1f %7.1f\n", s, d.x.size(),
                same_support(before.model, truth) ? "exact" : "wrong", 100 * max_rel_moment(before.model, truth),
                support_of(before.model).c_str(), ok_support ? "yes" : "NO", sc.max_z, 100 * sc.max_rel, sc.covered,
                sc.total, wall, cpu);
    std::fflush(stdout);
  }
  std::printf("summary %s dt %.3f noise %.2f: before exact support %d/%d; likelihood exact support %d/%d, "
              "all within 3 SE and 5 %% %d/%d, 95 %% coverage %.1f %% (%d/%d)\n",
              which.c_str(), dt, noise_share, before_exact, seeds, exact, seeds, within, seeds,
              100.0 * covered / std::max(total, 1), covered, total);
  std::printf("per parameter over seeds (measurement_sd: relative to its own truth, which varies by seed): mean z, sd of z, "
              "mean relative error +- its SE (the bias estimate), 95 %% coverage\n");
  print_bias(which, signed_errors);
  if (second) {
    std::printf("the same estimates with %s standard errors (VEHS_SECOND_COVARIANCE=%s; x sqrt(1 + 1/B) when corrected):\n",
                second_method.c_str(), second);
    print_bias(which, second_errors);
    if (!uncorrected_errors.empty()) {
      std::printf("the maximum before the bias correction, with its own %s standard errors (\"zu\"):\n",
                  second_method.c_str());
      print_bias(which, uncorrected_errors);
    }
  }
  std::printf("\n");
  return 0;
}

std::vector<double> broadband(std::size_t n, double dt, std::uint64_t seed) {
  return likelihood::random_phase_multisine(n, dt, 40, 0.05, 0.09, seed);
}

int driven(int seeds) {
  const Model truth = parse(R"({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.15, "u": 1.0}, "diffusion": {"1": 0.002}})");
  const double dt = 2.0 * M_PI / 10.0;
  const std::size_t n = 4000;
  std::printf("# driven Duffing, 10 samples per period, 2 %% sensor noise, 8 records x %zu samples; library x, x^2, x^3, y, x^2*y, u\n", n);
  std::printf("%-5s | %-6s %7s | %-6s %7s %7s %6s | %9s %9s %6s\n", "seed", "before", "rel.err", "exact", "max|z|", "rel.err",
              "cover", "free-run", "floor", "ratio");
  int exact = 0, within = 0, covered = 0, total = 0, ratio_ok = 0;
  double worst_ratio = 0;
  for (int s = 0; s < seeds; ++s) {
    const auto u = broadband(n, dt, 3 + std::uint64_t(s));
    const double sd = sd_of(simulate(truth, dt, 1, double(n) * dt, 500 + std::uint64_t(s), 0.0, &u).x);
    const double noise = 0.02 * sd;
    const Dataset d = simulate(truth, dt, 8, double(n) * dt, 500 + std::uint64_t(s), noise, &u);
    identify::Options io;
    io.drift_library = terms({"x", "x^2", "x^3", "y", "x^2*y", "u"});
    io.diffusion_library = terms({"1"});
    const identify::Result before = identify::identify(d, io);
    io.sparsity = identify::Sparsity::None;
    const identify::Result start = identify::identify(d, io);
    likelihood::RefineOptions o;
    o.select = true;
    const auto r = likelihood::refine({start.model, 0.0, {}}, d, o);
    const bool ok = same_support(r.model.model, truth) && r.find("measurement_sd") >= 0;
    const Score sc = score(r, truth, noise);
    const auto u2 = broadband(n, dt, 10000 + std::uint64_t(s));
    const Dataset test = simulate(truth, dt, 1, double(n) * dt, 9000 + std::uint64_t(s), noise, &u2);
    const std::vector<double> x(test.x.begin(), test.x.end());
    const double fit = likelihood::validate_free_run(r.model.model, x, u2, dt, 50).rmse;
    const double floor = likelihood::validate_free_run(truth, x, u2, dt, 50).rmse;
    exact += ok;
    within += sc.max_z <= 3 && sc.max_rel <= 0.05;
    covered += sc.covered;
    total += sc.total;
    ratio_ok += fit <= 1.2 * floor;
    worst_ratio = std::max(worst_ratio, fit / floor);
    std::printf("%-5d | %-6s %6.1f%% | %-6s %7.2f %6.1f%% %3d/%-2d | %9.4f %9.4f %6.3f\n", s,
                same_support(before.model, truth) ? "exact" : "wrong", 100 * max_rel_moment(before.model, truth),
                ok ? "yes" : "NO", sc.max_z, 100 * sc.max_rel, sc.covered, sc.total, fit, floor, fit / floor);
    std::fflush(stdout);
  }
  std::printf("summary driven: exact support %d/%d, within 3 SE and 5 %% %d/%d, coverage %.1f %% (%d/%d), "
              "free run <= 1.2x floor %d/%d (worst ratio %.3f)\n\n",
              exact, seeds, within, seeds, 100.0 * covered / total, covered, total, ratio_ok, seeds, worst_ratio);
  return 0;
}

Effect effect(EffectId id, std::map<std::string, double> p) {
  Effect e;
  e.id = id;
  e.params = std::move(p);
  return e;
}

int effects(int seeds, int first_seed, const std::string& only) {
  std::printf("# dynamic effects by the likelihood (dt 0.25, 1 %% sensor noise, start: truth +20 %%, omega +0.1 %%)\n");
  std::printf("%-28s %-5s %8s %8s | worst effect param: rel.err, |z|\n", "effect", "seed", "max|z|", "rel.err");
  std::map<std::string, std::pair<int, int>> tally;
  // per effect and parameter: signed z and signed relative error of every seed (bias vs tail)
  std::map<std::string, SignedErrors> signed_errors;
  for (const std::string which : {"electromechanical_coupling", "colored_noise", "harmonic_forcing"}) {
    if (!only.empty() && which != only) continue;
    for (int s = first_seed; s < first_seed + seeds; ++s) {
      likelihood::ObservedModel truth{bistable(), 0.01, {}};
      Dataset d;
      const std::uint64_t seed = 700 + std::uint64_t(s);
      if (which == "electromechanical_coupling") {
        truth.model.effects = {effect(EffectId::ElectromechanicalCoupling, {{"lambda", 0.6}, {"coupling", 0.4}})};
        d = simulate(truth.model, 0.25, 8, 2000.0, seed, 0.01);
      } else if (which == "colored_noise") {
        truth.model = parse(R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.2}, "diffusion": {"1": 0.005}})");
        truth.model.effects = {effect(EffectId::ColoredNoise, {{"tau", 1.0}, {"intensity", 0.04}})};
        d = simulate(truth.model, 0.25, 8, 2500.0, seed, 0.01);
      } else {
        truth.model.effects = {effect(EffectId::HarmonicForcing, {{"amplitude", 0.12}, {"omega", 0.8}, {"phase", 0.0}})};
        std::mt19937_64 g(seed);
        std::uniform_real_distribution<double> ph(-M_PI, M_PI);
        for (int r = 0; r < 6; ++r) {
          Model m = truth.model;
          m.effects[0].params["phase"] = ph(g);
          truth.record_phases.push_back(m.effects[0].params["phase"]);
          Dataset one = simulate(m, 0.25, 1, 1500.0, seed * 10 + std::uint64_t(r), 0.01);
          d.append(std::move(one));
        }
      }
      likelihood::ObservedModel start = truth;
      for (auto& tc : start.model.drift) tc.coef *= 1.2;
      for (auto& tc : start.model.diffusion) tc.coef *= 0.8;
      for (auto& e : start.model.effects)
        for (auto& [k, v] : e.params)
          if (k != "phase") v *= k == "omega" ? 1.001 : 1.2;
      for (auto& p : start.record_phases) p += 0.2;
      likelihood::RefineOptions o;
      o.per_record_phase = which == "harmonic_forcing";
      if (std::getenv("VEHS_PROGRESS")) o.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
      const auto r = likelihood::refine(start, d, o);
      if (std::getenv("VEHS_PROGRESS"))
        for (std::size_t i = 0; i < r.parameters.size(); ++i)
          std::fprintf(stderr, "  %-18s %12.6g +- %10.3g\n", r.parameters[i].name.c_str(), r.values[i], r.stderrs[i]);
      double max_z = 0, rel = 0, ez = 0;
      auto one = [&](const std::string& name, double v, bool is_effect) {
        const int i = r.find(name);
        if (i < 0) return;
        double diff = r.values[std::size_t(i)] - v;
        if (name.rfind("phase[", 0) == 0) diff = std::remainder(diff, 2 * M_PI);
        const double z = std::abs(diff) / r.stderrs[std::size_t(i)];
        max_z = std::max(max_z, z);
        if (name.rfind("phase[", 0) != 0)
          signed_errors[which][name].push_back({diff / r.stderrs[std::size_t(i)], diff / std::abs(v)});
        if (is_effect) {
          rel = std::max(rel, std::abs(diff / v));
          ez = std::max(ez, z);
        }
      };
      for (const auto& tc : truth.model.drift) one("drift[" + tc.term.name() + "]", tc.coef, false);
      for (const auto& tc : truth.model.diffusion) one("diffusion[" + tc.term.name() + "]", tc.coef, false);
      for (const auto& e : truth.model.effects)
        for (const auto& [k, v] : e.params)
          if (k != "phase" || !o.per_record_phase) one(e.name() + "." + k, v, true);
      for (std::size_t i = 0; i < truth.record_phases.size(); ++i) one("phase[" + std::to_string(i) + "]", truth.record_phases[i], false);
      std::printf("%-28s %-5d %8.2f %8.2f | effect params: max rel.err %.1f %%, max |z| %.2f\n", which.c_str(), s, max_z,
                  100 * rel, 100 * rel, ez);
      std::fflush(stdout);
      auto& t = tally[which];
      t.first += max_z <= 3.0 && rel <= 0.15;
      t.second += 1;
    }
  }
  for (const auto& [k, v] : tally)
    std::printf("summary %s: all within 3 SE and effect params within 15 %%: %d/%d\n", k.c_str(), v.first, v.second);
  std::printf("per parameter over seeds: mean z (its SE 1/sqrt(n) if the SEs are calibrated), sd of z, mean relative "
              "error +- its SE, 95 %% coverage\n");
  for (const auto& [which, params] : signed_errors) print_bias(which, params);
  std::printf("\n");
  return 0;
}

int speed(double max_samples) {
  std::printf("# speed: bistable Duffing (dt 0.35, 2 %% sensor noise), refine from a 10 %%-perturbed start, "
              "5 parameters, observed-information SEs; %d threads\n", omp_get_max_threads());
  std::printf("%-10s %8s %8s %8s %8s %10s\n", "samples", "wall s", "cpu s", "grads", "substeps", "us/sample");
  const Model truth = bistable();
  for (double T : {35000.0, 105000.0, 350000.0}) {
    if (T / 0.35 > 1.01 * max_samples) break;
    const Dataset d = simulate(truth, 0.35, 10, T / 10.0, 77, 0.02);
    likelihood::ObservedModel start{truth, 0.02, {}};
    for (auto& tc : start.model.drift) tc.coef *= 1.1;
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    const auto r = likelihood::refine(start, d, {});
    const double wall = seconds_since(t0), cpu = cpu_seconds() - c0;
    std::printf("%-10zu %8.2f %8.2f %8d %8d %10.2f\n", d.x.size(), wall, cpu, r.summary.gradient_evaluations,
                r.summary.substeps, 1e6 * wall / double(d.x.size()));
    std::fflush(stdout);
  }
  std::printf("\n");
  return 0;
}


/// Bootstrap particle filter of the same observed model (drift and diffusion of the model, additive noise):
/// semi-implicit Euler–Maruyama (velocity first: explicit Euler would add energy at a rate
/// comparable to the damping) with 40 substeps per interval, systematic resampling, the
/// filter's priors.
double particle_log_likelihood(const Model& m, double r, const Dataset& d, int particles, std::uint64_t seed) {
  const double dt = d.records[0].dt;
  const int sub = 40;
  const double h = dt / sub;
  double s2 = 0, nd = 0;
  for (const auto& rec : d.records)
    for (std::size_t k = 0; k + 1 < rec.size; ++k) {
      const double v = (d.x_of(rec)[k + 1] - d.x_of(rec)[k]) / dt;
      s2 += v * v;
      nd += 1;
    }
  const double ysd = std::sqrt(2 * s2 / nd);
  double ll = 0;
  for (const auto& rec : d.records) {
    const double* xo = d.x_of(rec);
    std::vector<double> x(static_cast<std::size_t>(particles)), y(static_cast<std::size_t>(particles)), w(static_cast<std::size_t>(particles));
    std::mt19937_64 g(seed * 1000 + std::uint64_t(rec.id));
    std::normal_distribution<double> nrm;
    for (int i = 0; i < particles; ++i) {
      x[std::size_t(i)] = xo[0] + r * nrm(g);
      y[std::size_t(i)] = ysd * nrm(g);
    }
    for (std::size_t k = 1; k < rec.size; ++k) {
#pragma omp parallel
      {
        std::mt19937_64 gl(seed * 7919 + k * 131 + std::uint64_t(omp_get_thread_num()) + std::uint64_t(rec.id) * 1000003);
        std::normal_distribution<double> n2;
#pragma omp for
        for (int i = 0; i < particles; ++i) {
          double a = x[std::size_t(i)], b = y[std::size_t(i)];
          for (int j = 0; j < sub; ++j) {  // semi-implicit (symplectic) Euler: no energy drift
            b += m.b2(a, b) * h + std::sqrt(std::max(m.a22(a, b), 0.0) * h) * n2(gl);
            a += b * h;
          }
          x[std::size_t(i)] = a;
          y[std::size_t(i)] = b;
        }
      }
      double mx = -INFINITY;
      for (int i = 0; i < particles; ++i) {
        const double e = xo[k] - x[std::size_t(i)];
        w[std::size_t(i)] = -0.5 * e * e / (r * r);
        mx = std::max(mx, w[std::size_t(i)]);
      }
      double sum = 0;
      for (auto& v : w) sum += (v = std::exp(v - mx));
      ll += mx + std::log(sum / particles) - 0.5 * std::log(2 * M_PI * r * r);
      // systematic resampling
      std::vector<double> nx(x.size()), ny(y.size());
      const double step = sum / particles;
      double u = std::uniform_real_distribution<double>(0, step)(g), c = w[0];
      std::size_t j = 0;
      for (int i = 0; i < particles; ++i) {
        while (u > c && j + 1 < w.size()) c += w[++j];
        nx[std::size_t(i)] = x[j];
        ny[std::size_t(i)] = y[j];
        u += step;
      }
      x.swap(nx);
      y.swap(ny);
    }
  }
  return ll;
}

int gaussian() {
  std::printf("# Gaussian filter vs particle filter (5000 particles, semi-implicit Euler-Maruyama h = dt/40, 4 runs for its "
              "Monte Carlo error): bistable U = -x^2/2 + x^4/4, beta 0.1, 2D = 0.04 (and 2D = 0.16: barrier/noise 4x "
              "lower, frequent crossings), sensor noise 0.05, 2 records x 250 samples\n");
  std::printf("%-6s %-5s %12s %12s %9s %14s %14s %9s\n", "2D", "dt", "logL filter", "logL PF", "PF se",
              "dlogL(b) filt", "dlogL(b) PF", "PF se");
  for (double D2 : {0.04, 0.16})
    for (double dt : {0.35, 0.7, 1.4}) {
      Model truth = bistable();
      truth.diffusion[0].coef = D2;
      const Dataset d = simulate(truth, dt, 2, 250 * dt, 4242, 0.05);
      Model alt = truth;
      for (auto& tc : alt.drift)
        if (tc.term == Term::parse("y")) tc.coef = -0.13;
      likelihood::FilterOptions fo;
      fo.substeps = 16;
      const double lf = likelihood::log_likelihood({truth, 0.05, {}}, d, fo).log_likelihood;
      const double lfa = likelihood::log_likelihood({alt, 0.05, {}}, d, fo).log_likelihood;
      std::vector<double> lp, dl;
      for (std::uint64_t s = 1; s <= 4; ++s) {
        const double a = particle_log_likelihood(truth, 0.05, d, 5000, s);
        const double b = particle_log_likelihood(alt, 0.05, d, 5000, s);
        lp.push_back(a);
        dl.push_back(a - b);
      }
      auto mean_se = [](const std::vector<double>& v) {
        double m = 0, q = 0;
        for (double x : v) m += x;
        m /= double(v.size());
        for (double x : v) q += (x - m) * (x - m);
        return std::pair<double, double>{m, std::sqrt(q / double(v.size() - 1) / double(v.size()))};
      };
      const auto [pm, pse] = mean_se(lp);
      const auto [dm, dse] = mean_se(dl);
      std::printf("%-6.2f %-5.2f %12.2f %12.2f %9.2f %14.2f %14.2f %9.2f\n", D2, dt, lf, pm, pse, lf - lfa, dm, dse);
      std::fflush(stdout);
    }
  std::printf("(dlogL(b): log L at beta 0.1 minus at beta 0.13 — what the estimate depends on)\n\n");
  return 0;
}

int silverbox(const std::string& csv) {
  ReadOptions ro;
  ro.x_column = "V2";
  ro.u_column = "V1";
  ro.dt = 0.0016384;
  ro.require_u = true;
  Dataset all = read_measurements(csv, ro);
  subtract_record_means(all);
  const std::size_t e0 = 40650, e1 = 40650 + std::size_t(0.75 * (127400 - 40650));
  const Dataset est = likelihood::slice_record(all, 0, e0, e1);
  struct Split { const char* name; std::size_t a, b; };
  const Split tests[] = {{"arrow", 100, 40575}, {"arrow, no extrapolation", 100, 32100}, {"multisine test", e1, 127400}};
  auto scores = [&](const Model& m, likelihood::InputInterpolation how) {
    likelihood::FreeRunOptions fo;
    fo.input = how;
    std::string out;
    for (const auto& t : tests) {
      const std::vector<double> x(all.x.begin() + long(t.a), all.x.begin() + long(t.b));
      const std::vector<double> u(all.u.begin() + long(t.a), all.u.begin() + long(t.b));
      char buf[64];
      try {
        std::snprintf(buf, sizeof buf, " %8.3f", 1e3 * likelihood::validate_free_run(m, x, u, ro.dt, 50, fo).rmse);
      } catch (const Error&) {
        std::snprintf(buf, sizeof buf, " %8s", "diverges");
      }
      out += buf;
    }
    return out;
  };
  std::printf("# Silverbox (SNLS80mV), estimation [%zu, %zu), free-run RMSE in mV after 50 samples "
              "(output rms on the arrow 53.4 mV)\n", e0, e1);
  std::printf("%-66s %8s %8s %8s %6s %7s\n", "model", "arrow", "no-extr", "msine", "terms", "seconds");
  identify::Options io;
  io.drift_library = terms({"1", "x", "x^2", "x^3", "y", "x*y", "x^2*y", "u"});
  io.diffusion_library = terms({"1", "x^2"});
  for (auto est_kind : {identify::Estimator::Auto, identify::Estimator::Uli}) {
    io.estimator = est_kind;
    const auto r = identify::identify(est, io);
    std::printf("%-66s%s %6zu %7s\n", (std::string("before: identify, estimator ") + enum_to_string(identify::kEstimatorNames, est_kind)).c_str(),
                scores(r.model, likelihood::InputInterpolation::ZeroOrderHold).c_str(), r.model.drift.size(), "");
  }
  io.estimator = identify::Estimator::Uli;
  io.sparsity = identify::Sparsity::None;
  io.diffusion_library = terms({"1"});
  const auto start = identify::identify(est, io);
  io.diffusion_library = terms({"1", "x^2"});
  const auto start_x2 = identify::identify(est, io);
  // the physical model: output offset, asymmetric and cubic spring, damping, input gain
  Model physical = start.model;
  physical.drift.erase(std::remove_if(physical.drift.begin(), physical.drift.end(),
                                      [](const TermCoef& tc) { return tc.term == Term::parse("x*y") || tc.term == Term::parse("x^2*y"); }),
                       physical.drift.end());
  struct Row { std::string name; const Model* start; bool select; likelihood::InputInterpolation how; };
  using II = likelihood::InputInterpolation;
  const Row rows[] = {
      {"likelihood, BIC from the 8 drift terms, a22 = const, input zoh", &start.model, true, II::ZeroOrderHold},
      {"likelihood, BIC from the 8 drift terms, a22 = const, input linear", &start.model, true, II::Linear},
      {"likelihood, BIC from the 8 drift terms, a22 = const, input cubic", &start.model, true, II::Cubic},
      {"likelihood, BIC from the 8 drift terms, a22 = const, band_limited", &start.model, true, II::BandLimited},
      {"likelihood, BIC from 8 drift terms and a22 = 1, x^2, band_limited", &start_x2.model, true, II::BandLimited},
      {"likelihood, physical 6 terms (1,x,x^2,x^3,y,u), band_limited", &physical, false, II::BandLimited},
  };
  for (const Row& row : rows) {
    likelihood::RefineOptions o;
    o.filter.input = row.how;
    o.select = row.select;
    o.covariance = likelihood::Covariance::Fisher;
    const auto t0 = Clock::now();
    likelihood::Result r;
    try {
      r = likelihood::refine({*row.start, 0.0, {}}, est, o);
    } catch (const Error& e) {
      std::printf("%-66s error: %s\n", row.name.c_str(), e.what());
      continue;
    }
    const double sec = seconds_since(t0);
    std::size_t n = 0;
    for (const auto& tc : r.model.model.drift) n += tc.coef != 0.0;
    std::printf("%-66s%s %6zu %7.1f\n", row.name.c_str(), scores(r.model.model, row.how).c_str(), n, sec);
    std::printf("    log L %.1f; %s\n", r.log_likelihood, r.summary.BriefReport().c_str());
    for (std::size_t i = 0; i < r.parameters.size(); ++i)
      std::printf("    %-18s %16.8g +- %10.3g\n", r.parameters[i].name.c_str(), r.values[i], r.stderrs[i]);
    for (const auto& st : r.summary.selection)
      std::printf("    selection: remove %-14s |z| %8.3g, 2 dlogL %10.4g vs %.3g: %s\n", st.removed.c_str(), st.z, st.delta,
                  st.threshold, st.accepted ? "removed" : "kept");
    if (std::getenv("VEHS_SILVERBOX_MODEL") && !row.select)
      std::printf("    model file: %s\n", model_to_json(r.model.model).dump().c_str());
    std::fflush(stdout);
  }
  std::printf("\n");
  return 0;
}

/// A parameter of the truth perturbed by a relative step: drift or diffusion coefficient by
/// name, or "measurement_sd".
struct Perturbed {
  Model model;
  double r;
};
Perturbed perturb(const Model& truth, double r, const std::string& name, double rel) {
  Perturbed p{truth, r};
  if (name == "measurement_sd") p.r *= 1 + rel;
  for (auto& tc : p.model.diffusion)
    if ("diffusion[" + tc.term.name() + "]" == name) tc.coef *= 1 + rel;
  for (auto& tc : p.model.drift)
    if ("drift[" + tc.term.name() + "]" == name) tc.coef *= 1 + rel;
  return p;
}
double value_of(const Model& truth, double r, const std::string& name) {
  if (name == "measurement_sd") return r;
  for (const auto& tc : truth.diffusion)
    if ("diffusion[" + tc.term.name() + "]" == name) return tc.coef;
  for (const auto& tc : truth.drift)
    if ("drift[" + tc.term.name() + "]" == name) return tc.coef;
  return 0;
}

/// Mean and SE of a list.
std::pair<double, double> mean_se(const std::vector<double>& v) {
  const double n = double(v.size());
  double m = 0, q = 0;
  for (double x : v) m += x / n;
  for (double x : v) q += (x - m) * (x - m) / (n - 1);
  return {m, std::sqrt(q / n)};
}

/// The score at the truth, ∂log L/∂θ by central differences of the filter's log L, over seeds:
/// the exact likelihood's score has mean 0 at the truth, so a mean score several SEs from 0 is
/// a bias of the filter's estimating equation (present at any record length; not a finite-sample
/// effect). Its size in estimate units: I⁻¹·E[score], with I the covariance of the scores over
/// seeds (information identity). The same data under variants separate the causes (paired
/// differences against the first): substeps (4x the automatic), block-start priors (blocks of
/// 512 samples: 8x the block starts), and the noise-free record of the same path (also the
/// generator check: noisy − clean must be white with sd = measurement_sd). With PF_RECORDS > 0,
/// the particle filter's score on the first PF_RECORDS records, paired with the filter's on them.
int score_study(const std::string& which, double dt, double noise_share, int seeds, double T, int records,
                int pf_records, int particles) {
  const Model truth = which == "paper" ? paper() : bistable();
  std::printf("# score at the truth: %s dt %.3f noise %.2f*sd(x), %d records x %.0f time units, %d seeds; d logL/d theta "
              "by central differences (h = 1e-3 relative)\n", which.c_str(), dt, noise_share, records, T, seeds);
  struct Variant { const char* name; int substeps_factor; std::size_t block; bool clean; };
  const Variant variants[] = {{"noisy, automatic substeps", 1, 1 << 14, false},
                              {"noisy, 4x substeps", 4, 1 << 14, false},
                              {"noisy, blocks of 512 (8x priors)", 1, 512, false},
                              {"clean (no sensor noise), same path", 1, 1 << 14, true}};
  std::vector<std::string> names;
  for (const auto& tc : truth.drift) names.push_back("drift[" + tc.term.name() + "]");
  for (const auto& tc : truth.diffusion) names.push_back("diffusion[" + tc.term.name() + "]");
  if (noise_share > 0) names.push_back("measurement_sd");
  const std::size_t nv = std::size(variants), np = names.size();
  std::vector<std::vector<Eigen::VectorXd>> scores(nv);
  std::vector<double> pf_diff, pf_filter, pf_pf;
  double gen_sd = 0, gen_r1 = 0;
  int subs = 0;
  auto score_of = [&](const Dataset& d, double r, const std::string& name, const likelihood::FilterOptions& fo) {
    const double h = 1e-3, c = value_of(truth, r, name);
    auto at = [&](double rel) {
      const Perturbed p = perturb(truth, r, name, rel);
      return likelihood::log_likelihood({p.model, p.r, {}}, d, fo).log_likelihood;
    };
    return (at(h) - at(-h)) / (2 * h * c);
  };
  for (int s = 0; s < seeds; ++s) {
    const std::uint64_t seed = 1000 + std::uint64_t(s);
    const double sd = sd_of(simulate(truth, dt, 2, T, seed, 0.0).x);
    const double noise = noise_share * sd;
    const Dataset noisy = simulate(truth, dt, records, T, seed, noise);
    const Dataset clean = simulate(truth, dt, records, T, seed, 0.0);
    if (noise > 0) {  // the generator: noisy − clean
      double s2 = 0, c1 = 0;
      for (std::size_t i = 0; i < noisy.x.size(); ++i) {
        const double e = noisy.x[i] - clean.x[i];
        s2 += e * e;
        if (i > 0) c1 += e * (noisy.x[i - 1] - clean.x[i - 1]);
      }
      gen_sd += std::sqrt(s2 / double(noisy.x.size())) / noise / seeds;
      gen_r1 += c1 / s2 / seeds;
    }
    for (std::size_t v = 0; v < nv; ++v) {
      likelihood::FilterOptions fo;
      fo.block_samples = variants[v].block;
      const Dataset& d = variants[v].clean ? clean : noisy;
      const double r = variants[v].clean ? 0.0 : noise;
      const int auto_sub = likelihood::log_likelihood({truth, r, {}}, d, fo).substeps;
      subs = std::max(subs, auto_sub);
      fo.substeps = auto_sub * variants[v].substeps_factor;
      Eigen::VectorXd g = Eigen::VectorXd::Zero(long(np));
      for (std::size_t j = 0; j < np; ++j)
        if (!(variants[v].clean && names[j] == "measurement_sd")) g[long(j)] = score_of(d, r, names[j], fo);
      scores[v].push_back(g);
    }
    if (pf_records > 0) {  // 2Q: the filter's and the particle filter's score on the same records
      const Dataset small = simulate(truth, dt, pf_records, T, seed, noise);
      const std::string name = "diffusion[x^2]";
      const double h = 0.05, c = value_of(truth, noise, name);
      const double sf = score_of(small, noise, name, {});
      const Perturbed up = perturb(truth, noise, name, h), dn = perturb(truth, noise, name, -h);
      const double sp = (particle_log_likelihood(up.model, noise, small, particles, seed) -
                         particle_log_likelihood(dn.model, noise, small, particles, seed)) / (2 * h * c);
      pf_filter.push_back(sf);
      pf_pf.push_back(sp);
      pf_diff.push_back(sf - sp);
    }
    if (std::getenv("VEHS_PROGRESS")) std::fprintf(stderr, "seed %d done\n", s);
  }
  if (noise_share > 0)
    std::printf("generator: rms(noisy - clean)/measurement_sd %.4f, lag-1 correlation %+.4f (white: 1, 0 +- %.4f)\n",
                gen_sd, gen_r1, 1 / std::sqrt(double(records) * T / dt * seeds));
  std::printf("filter substeps (automatic) %d\n", subs);
  std::printf("%-36s %-16s %11s %9s %9s %8s %11s %9s\n", "variant", "parameter", "mean score", "+- SE", "sd", "mean/sd",
              "diff vs 1st", "+- SE");
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t j = 0; j < np; ++j) {
      if (variants[v].clean && names[j] == "measurement_sd") continue;
      std::vector<double> col, diff;
      for (std::size_t k = 0; k < scores[v].size(); ++k) {
        col.push_back(scores[v][k][long(j)]);
        diff.push_back(scores[v][k][long(j)] - scores[0][k][long(j)]);
      }
      const auto [mu, se] = mean_se(col);
      const auto [md, sed] = mean_se(diff);
      const double sd = se * std::sqrt(double(col.size()));
      std::printf("%-36s %-16s %11.4g %9.3g %9.3g %+8.3f %11.4g %9.3g\n", variants[v].name, names[j].c_str(), mu, se, sd,
                  mu / sd, md, sed);
    }
  std::printf("(mean/sd: the score's bias in units of its sd = sqrt(Fisher information of that parameter alone); "
              "diff vs 1st: the paired difference of the scores on the same data, variant minus the first)\n");
  if (pf_records > 0) {
    const auto [mf, sf] = mean_se(pf_filter);
    const auto [mp, sp] = mean_se(pf_pf);
    const auto [md, sd] = mean_se(pf_diff);
    std::printf("diffusion[x^2] score on %d record(s) per seed, particle filter %d particles (h = 5 %%, common random "
                "numbers): filter %.4g +- %.3g, particle filter %.4g +- %.3g, filter - particle filter %.4g +- %.3g\n",
                pf_records, particles, mf, sf, mp, sp, md, sd);
  }
  std::printf("\n");
  return 0;
}

/// The spread of the estimate, from the score at the truth (issue 12: the maximum's z had sd
/// 1.4-1.7 over seeds 0-19 at omega dt 1.0 with 128 records). The one Fisher-scoring step from
/// the truth, theta + F^-1 g (autodiff g and F through the filter, likelihood::score_test with
/// every parameter tested), is the maximum to first order (on seed 9 of that study: the same
/// values to 0.00 SE). Its z per seed; the sd of z over seeds with its 95 % interval, by blocks
/// of 20 seeds and over all; and the sd that the pooled per-record score covariance predicts
/// (records are independent: Var g = R Cov(record score)), which the Fisher information alone
/// should match (ratio 1) when the filter's information is right. VEHS_SPREAD_REFIT=0,4,9: on
/// those seeds also the maximum itself (refine from the truth), against the step: the largest
/// |difference|/SE and 2(log L(max) − log L(truth)) beside gᵀF⁻¹g.
int spread(const std::string& which, double dt, int seeds, double T, int records) {
  const Model truth = which == "paper" ? paper() : bistable();
  std::vector<std::string> names;
  for (const auto& tc : truth.drift) names.push_back("drift[" + tc.term.name() + "]");
  for (const auto& tc : truth.diffusion) names.push_back("diffusion[" + tc.term.name() + "]");
  const long np = long(names.size());
  std::printf("# one-step z at the truth: %s dt %.3f, %d records x %.0f time units, seeds 0-%d (the data of `synthetic`), "
              "generator substeps %s\n", which.c_str(), dt, records, T, seeds - 1,
              std::getenv("VEHS_GEN_SUBSTEPS") ? std::getenv("VEHS_GEN_SUBSTEPS") : "40");
  std::vector<Eigen::VectorXd> z1;
  Eigen::MatrixXd Fsum = Eigen::MatrixXd::Zero(np, np), S2 = Eigen::MatrixXd::Zero(np, np);
  Eigen::VectorXd S1 = Eigen::VectorXd::Zero(np);
  double nrec = 0;
  const std::string refit = std::getenv("VEHS_SPREAD_REFIT") ? "," + std::string(std::getenv("VEHS_SPREAD_REFIT")) + "," : "";
  for (int s = 0; s < seeds; ++s) {
    const Dataset d = simulate(truth, dt, records, T, 1000 + std::uint64_t(s), 0.0);
    const auto r = likelihood::score_test({truth, 0.0, {}}, d, names);
    Eigen::VectorXd z(np);
    for (long j = 0; j < np; ++j) z[j] = (r.estimate[std::size_t(j)] - r.null_value[std::size_t(j)]) / r.stderrs[std::size_t(j)];
    z1.push_back(z);
    if (refit.find("," + std::to_string(s) + ",") != std::string::npos) {
      likelihood::RefineOptions ro;
      ro.estimate_measurement_noise = false;
      ro.filter.substeps = r.substeps;
      const likelihood::Result m = likelihood::refine({truth, 0.0, {}}, d, ro);
      double worst = 0;
      for (long j = 0; j < np; ++j) {
        const int i = m.find(names[std::size_t(j)]);
        worst = std::max(worst, std::abs(m.values[std::size_t(i)] - r.estimate[std::size_t(j)]) / m.stderrs[std::size_t(i)]);
      }
      std::printf("seed %-4d the maximum: largest |maximum - step|/SE %.3f, 2(log L(max) - log L(truth)) %.2f, "
                  "g'F^-1 g %.2f\n", s, worst, 2 * (m.log_likelihood - r.log_likelihood), r.statistic);
    }
    Fsum += r.efficient_information;
    for (long k = 0; k < r.record_scores.rows(); ++k) {
      const Eigen::VectorXd g = r.record_scores.row(k).transpose();
      S1 += g, S2 += g * g.transpose(), nrec += 1;
    }
    std::printf("seed %-4d S %7.2f (chi2 %ld) z", s, r.statistic, np);
    for (long j = 0; j < np; ++j) std::printf(" %+.2f", z[j]);
    std::printf("\n");
    std::fflush(stdout);
  }
  const Eigen::MatrixXd Fi = (Fsum / seeds).inverse();
  const Eigen::MatrixXd C = (S2 - S1 * S1.transpose() / nrec) / (nrec - 1) * records;
  const Eigen::MatrixXd P = Fi * C * Fi;
  auto block = [&](int a, int b) {
    std::printf("seeds %d-%d:\n", a, b - 1);
    for (long j = 0; j < np; ++j) {
      std::vector<double> col;
      for (int k = a; k < b; ++k) col.push_back(z1[std::size_t(k)][j]);
      const double n = double(col.size());
      const auto [m, se] = mean_se(col);
      const double sd = se * std::sqrt(n);
      std::printf("  %-16s mean z %+.2f (+-%.2f)  sd z %.2f [%.2f, %.2f]", names[std::size_t(j)].c_str(), m, 1 / std::sqrt(n), sd,
                  sd * std::sqrt((n - 1) / chi2_quantile(n - 1, 0.975)), sd * std::sqrt((n - 1) / chi2_quantile(n - 1, 0.025)));
      if (a == 0 && b == seeds) std::printf("  predicted by the pooled records' scores %.3f", std::sqrt(P(j, j) / Fi(j, j)));
      std::printf("\n");
    }
  };
  for (int a = 0; a + 20 <= seeds && seeds > 20; a += 20) block(a, a + 20);
  if (seeds > 40) block(20, seeds);  // (the study that prompted this used seeds 0-19)
  block(0, seeds);
  // the z's move together: the share of their variance in the first principal component
  Eigen::MatrixXd Z(seeds, np);
  for (int k = 0; k < seeds; ++k) Z.row(k) = z1[std::size_t(k)].transpose();
  const Eigen::MatrixXd Zc = Z.rowwise() - Z.colwise().mean();
  const Eigen::VectorXd sd = (Zc.colwise().squaredNorm() / (seeds - 1)).cwiseSqrt();
  const Eigen::MatrixXd R = (Zc.transpose() * Zc / (seeds - 1)).cwiseQuotient(sd * sd.transpose());
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(R).eigenvalues();
  std::printf("first principal component of the z's correlation: %.0f %% of their variance\n", 100 * ev.maxCoeff() / ev.sum());
  std::printf("\n");
  return 0;
}

/// The filter's one-step predictions at the truth, calibrated against the data: the standardised
/// innovation z_k = (x_k − m_k)/√S_k has mean 0 and variance 1 under the exact predictive law, at
/// every level of the predicted |x|. Binned by |m_k|/sd(x), mean z·sign(m_k) and mean z² ± SE,
/// over all seeds' records. A mean z² above 1 where the drift is stiff means the Gaussian
/// predictive variance is too small there — what an estimate of a22's x² coefficient makes up for.
int innovations(const std::string& which, double dt, double noise_share, int seeds, double T, int records) {
  const Model truth = which == "paper" ? paper() : bistable();
  std::printf("# standardised innovations at the truth: %s dt %.3f noise %.2f*sd(x), %d seeds x %d records x %.0f time "
              "units\n", which.c_str(), dt, noise_share, seeds, records, T);
  const std::vector<double> edges = {0, 0.5, 1.0, 1.25, 1.5, 1.75, 2.0, 1e9};
  const std::size_t nb = edges.size() - 1;
  std::vector<std::vector<double>> z1(nb), z2(nb);
  for (int s = 0; s < seeds; ++s) {
    const std::uint64_t seed = 1000 + std::uint64_t(s);
    const double sd = sd_of(simulate(truth, dt, 2, T, seed, 0.0).x);
    const double noise = noise_share * sd;
    const Dataset d = simulate(truth, dt, records, T, seed, noise);
    const likelihood::FilterTrace tr = likelihood::filter_trace({truth, noise, {}}, d);
    for (std::size_t i = 0; i < d.x.size(); ++i) {
      if (!(tr.predicted_var[i] > 0)) continue;
      const double m = tr.predicted_x[i], z = (d.x[i] - m) / std::sqrt(tr.predicted_var[i]);
      std::size_t b = 0;
      while (b + 1 < nb && std::abs(m) / sd >= edges[b + 1]) ++b;
      z1[b].push_back(m >= 0 ? z : -z);
      z2[b].push_back(z * z);
    }
  }
  std::printf("%-12s %9s %16s %16s\n", "|m|/sd(x)", "samples", "mean z sign(m)", "mean z^2");
  for (std::size_t b = 0; b < nb; ++b) {
    if (z1[b].size() < 2) continue;
    const auto [a, as] = mean_se(z1[b]);
    const auto [q, qs] = mean_se(z2[b]);
    std::printf("%4.2f-%-7.2f %9zu %+8.4f +-%.4f %8.4f +-%.4f\n", edges[b], std::min(edges[b + 1], 99.0), z1[b].size(), a, as,
                q, qs);
  }
  std::printf("\n");
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string cmd = argc > 1 ? argv[1] : "";
    auto arg = [&](int i, double def) { return argc > i ? std::atof(argv[i]) : def; };
    if (cmd == "synthetic")
      return synthetic(argc > 2 ? argv[2] : "bistable", arg(3, 0.35), arg(4, 0.0), int(arg(5, 20)), arg(6, 8000), int(arg(7, 10)),
                       int(arg(8, 0)));
    if (cmd == "score")
      return score_study(argc > 2 ? argv[2] : "paper", arg(3, 0.236), arg(4, 0.02), int(arg(5, 20)), arg(6, 1000), int(arg(7, 8)),
                         int(arg(8, 0)), int(arg(9, 2000)));
    if (cmd == "innovations")
      return innovations(argc > 2 ? argv[2] : "paper", arg(3, 0.236), arg(4, 0.02), int(arg(5, 20)), arg(6, 1000), int(arg(7, 8)));
    if (cmd == "spread")
      return spread(argc > 2 ? argv[2] : "paper", arg(3, 0.236), int(arg(4, 40)), arg(5, 1000), int(arg(6, 128)));
    if (cmd == "driven") return driven(int(arg(2, 20)));
    if (cmd == "effects") return effects(int(arg(2, 20)), int(arg(3, 0)), argc > 4 ? argv[4] : "");
    if (cmd == "speed") return speed(arg(2, 1e6));
    if (cmd == "gaussian") return gaussian();
    if (cmd == "silverbox") return silverbox(argc > 2 ? argv[2] : "data/silverbox/SNLS80mV.csv");
    std::fprintf(stderr, "usage: bench_likelihood synthetic|score|spread|innovations|driven|effects|speed|silverbox|gaussian ...\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_likelihood: error: %s\n", e.what());
    return 1;
  }
}
