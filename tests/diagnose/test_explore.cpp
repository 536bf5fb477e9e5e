#include <catch2/catch.hpp>

#include <cstdio>
#include <iostream>

#include "diagnose_fixtures.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"

using namespace diag_test;

namespace {
void summary(const vehs::diagnose::Result& r) {
  std::printf("%-11s score %7.3f |", vehs::enum_to_string(vehs::diagnose::kVerdictNames, r.verdict).c_str(), r.score);
  for (const auto& c : r.components)
    std::printf(" %s p=%.3g(%g)", c.name.c_str(), c.test.available ? c.test.p_value : -1.0, c.test.dof);
  std::printf(" | sus:");
  for (const auto& s : r.suspects.ranked) std::printf(" %s %.1f z%.1f%s", s.effect.substr(0, 8).c_str(), s.evidence, s.z, s.held_out_significant ? "*" : "");
  std::printf(" | t=%.2f\n", total_seconds(r));
  std::printf("   %s\n", timings_text(r).c_str());
  for (std::size_t w = 0; w < std::min<std::size_t>(3, r.map.worst.size()); ++w) {
    const auto& b = r.map.bins[static_cast<std::size_t>(r.map.worst[w])];
    std::printf("   worst bin x=%.3f v=%.3f z=%.2f  lens=%s twins=%s/%d R=%d\n", b.x, b.v, b.z_mean,
                r.lens.describe().substr(0, 30).c_str(), vehs::enum_to_string(vehs::sim::kSchemeNames, r.sampling.twin_scheme).c_str(), r.sampling.twin_substeps, r.sampling.replicates);
  }
  for (const auto& w : r.warnings) std::printf("   warning: %s\n", w.c_str());
}
}  // namespace

TEST_CASE("explore: true model on its own data", "[bench][explore]") {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    DataSpec s;
    s.seed = 100 + seed;
    const auto m = bistable();
    const auto d = simulate(m, s);
    auto o = fast_options(seed);
    summary(vehs::diagnose::diagnose(m, d, o));
  }
}

TEST_CASE("explore: fitted baseline", "[bench][explore]") {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    DataSpec s;
    s.seed = 200 + seed;
    const auto d = simulate(bistable(), s);
    const auto m = fit(d, {"x", "x^3", "y"}, {"1", "x^2"});
    auto o = fast_options(seed);
    summary(vehs::diagnose::diagnose(m, d, o));
  }
}

TEST_CASE("explore: missing coulomb friction", "[bench][explore]") {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    DataSpec s;
    s.seed = 300 + seed;
    s.records = 32;
    s.samples = 10000;
    auto truth = bistable();
    truth.drift.push_back({vehs::Term::sign_y(), std::getenv("MU") ? -std::atof(std::getenv("MU")) : -0.1});
    vehs::canonicalize(truth.drift, "t");
    const auto d = simulate(truth, s);
    const auto m = fit(d, {"x", "x^3", "y"}, {"1", "x^2"});
    auto o = fast_options(seed);
    summary(vehs::diagnose::diagnose(m, d, o));
  }
}

TEST_CASE("explore: missing asymmetric stiffness", "[bench][explore]") {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    DataSpec s;
    s.seed = 400 + seed;
    s.records = 32;
    s.samples = 10000;
    auto truth = bistable();
    truth.drift.push_back({vehs::Term::monomial(2), -0.15});
    vehs::canonicalize(truth.drift, "t");
    const auto d = simulate(truth, s);
    const auto m = fit(d, {"x", "x^3", "y"}, {"1", "x^2"});
    auto o = fast_options(seed);
    summary(vehs::diagnose::diagnose(m, d, o));
  }
}

TEST_CASE("explore: null p-values", "[bench][explore_null]") {
  const char* env = std::getenv("VEHS_EXPLORE_N");
  const int n = env ? std::atoi(env) : 40;
  const char* fitted = std::getenv("VEHS_EXPLORE_FIT");
  const char* recs = std::getenv("VEHS_EXPLORE_RECORDS");
  const char* reps = std::getenv("VEHS_EXPLORE_R");
  for (int seed = 1; seed <= n; ++seed) {
    DataSpec s;
    s.seed = 1000 + static_cast<std::uint64_t>(seed);
    if (recs) s.records = std::atoi(recs);
    const auto d = simulate(bistable(), s);
    const auto m = fitted ? fit(d, {"x", "x^3", "y"}, {"1", "x^2"}) : bistable();
    auto o = fast_options(static_cast<std::uint64_t>(seed));
    o.suspects.enabled = false;
    o.fpk = false;
    if (reps) o.replicates = std::atoi(reps);
    const auto r = vehs::diagnose::diagnose(m, d, o);
    std::printf("P %d", seed);
    for (const auto& c : r.components) std::printf(" %s %.6g", c.name.c_str(), c.test.available ? c.test.p_value : -1.0);
    std::printf(" score %.4f draws %d\n", r.score, r.parameter_draws);
    for (const auto& w : r.warnings) std::printf("W %s\n", w.c_str());
    std::fflush(stdout);
  }
}

TEST_CASE("explore: paper-sized data", "[bench][explore_paper]") {
  const auto d = vehs::read_measurements(std::string("/tmp/dw/paper.npy"));
  const char* mp = std::getenv("VEHS_EXPLORE_MODEL");
  const auto m = vehs::load_model_file(mp ? mp : "/tmp/dw/learned.json");
  vehs::diagnose::Options o;
  o.progress = [](const vehs::ProgressEvent& e) {
    std::fprintf(stderr, "\r[%s] %lld/%lld", std::string(e.task).c_str(), e.done, e.total);
  };
  if (std::getenv("VEHS_EXPLORE_NOSUS")) o.suspects.enabled = false;
  const auto r = vehs::diagnose::diagnose(m, d, o);
  summary(r);
  std::printf("%s\n", timings_text(r).c_str());
  for (const auto& q : r.quantities)
    std::printf("%s data %.6g twin %.6g z %.3g\n", q.name.c_str(), q.data, q.twin, q.z);
}

TEST_CASE("explore: identify cost", "[bench][explore_id]") {
  DataSpec s;
  s.records = 32;
  s.samples = 10000;
  const auto d = simulate(bistable(), s);
  for (int rep = 0; rep < 3; ++rep) {
    vehs::identify::Options o;
    o.drift_library = {vehs::Term::parse("x"), vehs::Term::parse("x^3"), vehs::Term::parse("y")};
    o.diffusion_library = {vehs::Term::parse("1"), vehs::Term::parse("x^2")};
    o.sparsity = vehs::identify::Sparsity::None;
    o.estimator = vehs::identify::Estimator::Forward;
    if (rep > 0) o.folds = 1;
    if (rep > 1) o.pilot_samples = 20000;
    const auto r = vehs::identify::identify(d, o);
    std::printf("%.3f s", r.report.fit.seconds);
    for (const auto& [stage, seconds] : r.report.fit.timings) std::printf(" %s %.3f", stage.c_str(), seconds);
    std::printf("\n");
  }
}
