// diagnose-vehs on data whose missing physics is NOT in the catalogue (issue 13): velocity jumps
// of a compound Poisson process (impulsive excitation: heavy-tailed increments) on a bistable
// harvester. The data come from this file's own Euler–Maruyama loop (20 substeps per sample),
// a route the library never sees; the model is fitted by identify-vehs with the likelihood (as a
// user would: config files, the tools' main()), then diagnosed by diagnose-vehs. It must say
// inadequate, recommend no catalogue effect, and name the misfit as outside the catalogue with
// the held-out innovations' heavy tails. The control — the same generator with Coulomb friction
// hidden instead of the jumps — must still have coulomb_friction recommended.
//   VEHS_OC_VERBOSE=1 prints both conclusions; seed studies: scripts/seed-study.sh N
//   build/tests/test_diagnose "diagnose-vehs outside the catalogue*" (JOBS=1: files in /tmp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stat_bounds.hpp"
#include "tools/tools.hpp"

namespace fs = std::filesystem;

namespace {

/// The generator's physics: ẍ = x − x³ − β ẋ − μ sign(ẋ) + σ ξ(t) + Σ J_k δ(t − t_k), the jumps
/// J_k ~ N(0, jump_sd²) at the events of a Poisson process of the given rate.
struct Physics {
  double beta = 0.1, mu = 0.0, sigma = std::sqrt(0.02);
  double jump_rate = 0.0, jump_sd = 0.0;
};

/// Writes `records` records of `samples` samples at `dt` as CSV (traj, t, x): semi-implicit
/// Euler–Maruyama with `substeps` per sample after a burn-in of 50 time units.
void write_records(const std::string& path, const Physics& p, std::uint64_t seed, int records, int samples,
                   double dt) {
  constexpr int substeps = 20;
  const double h = dt / substeps;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::ofstream out(path);
  out << "traj,t,x\n";
  char line[96];
  for (int r = 0; r < records; ++r) {
    double x = 2.0 * uniform(rng) - 1.0, y = 0.0;
    auto step = [&] {
      double dy = (x - x * x * x - p.beta * y - p.mu * (y > 0.0 ? 1.0 : y < 0.0 ? -1.0 : 0.0)) * h +
                  p.sigma * std::sqrt(h) * normal(rng);
      if (p.jump_rate > 0.0 && uniform(rng) < p.jump_rate * h) dy += p.jump_sd * normal(rng);
      y += dy;
      x += y * h;
    };
    for (int k = 0; k < int(50.0 / h); ++k) step();
    for (int i = 0; i < samples; ++i) {
      std::snprintf(line, sizeof line, "%d,%.10g,%.17g\n", r, i * dt, x);
      out << line;
      for (int k = 0; k < substeps; ++k) step();
    }
  }
}

int run_tool(int (*main_fn)(int, char**), const std::string& name, const std::string& config) {
  std::vector<std::string> a{name, config, "--quiet"};
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  return main_fn(static_cast<int>(argv.size()), argv.data());
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

/// The suspects refitted to confirm them, with the outcome, and the components' p-values (VEHS_OC_VERBOSE).
void print_details(const nlohmann::json& j) {
  for (const auto& e : j["confirmation"]["effects"])
    std::printf("   refit %s: %s\n", e.value("effect", "").c_str(), e.value("reason", "").c_str());
  for (const auto& s : j["score_suspects"])
    std::printf("   score suspect %s z %.3g%s\n", s.value("effect", "").c_str(), s.value("z", 0.0),
                s.value("significant", false) ? " significant" : "");
  for (const auto& [name, t] : j["tests"].items())
    if (t.is_object() && t.contains("p_value") && t["p_value"].is_number())
      std::printf("   %s p %.3g\n", name.c_str(), t["p_value"].get<double>());
}

/// identify-vehs (the bistable terms, linear damping, constant noise; refined by the likelihood)
/// then diagnose-vehs as a user runs them; returns the diagnosis file.
nlohmann::json identify_and_diagnose(const fs::path& dir, const std::string& data, std::uint64_t seed) {
  const std::string model = (dir / "model.json").string(), diagnosis = (dir / "diagnosis.json").string();
  write_text(dir / "identify.json", R"({"data": ")" + data + R"(", "output": ")" + model +
                                        R"(", "drift_library": ["x", "x^3", "y"], "diffusion_library": ["1"],
      "sparsity": "none", "likelihood": {"covariance": "fisher"}})");
  REQUIRE(run_tool(vehs::tools::identify_main, "identify-vehs", (dir / "identify.json").string()) == 0);
  write_text(dir / "diagnose.json", R"({"model": ")" + model + R"(", "data": ")" + data + R"(", "output": ")" +
                                        diagnosis + R"(", "report": ")" + (dir / "report").string() +
                                        R"(", "replicates": 2, "parameter_draws": 4, "fpk": false, "seed": )" +
                                        std::to_string(seed) + "}");
  REQUIRE(run_tool(vehs::tools::diagnose_main, "diagnose-vehs", (dir / "diagnose.json").string()) == 0);
  std::ifstream in(diagnosis);
  return nlohmann::json::parse(in);
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Seed studies: the smallest component p over the verdict's threshold (log10), the refits'
/// largest held-out z, and the named effect's held-out z.
void tally_diagnosis(const std::string& label, const nlohmann::json& j, const std::string& effect) {
  double p_min = 1.0, z_max = -1e300, z_effect = 0.0;
  for (const auto& [name, t] : j["tests"].items())
    if (t.is_object() && t.contains("p_value") && t["p_value"].is_number())
      p_min = std::min(p_min, t["p_value"].get<double>());
  for (const auto& e : j["confirmation"]["effects"]) {
    const double z = e.contains("loglik_z") && e["loglik_z"].is_number() ? e["loglik_z"].get<double>() : -1e300;
    if (e.value("effect", "") == effect)
      z_effect = z;
    else
      z_max = std::max(z_max, z);
  }
  vehs_test::tally(label + " log10(min p / threshold)", std::log10(std::max(p_min, 1e-300) / j.value("threshold", 1.0)));
  if (z_max > -1e299) vehs_test::tally(label + " largest held-out z of the other refits", z_max);
  if (!effect.empty()) vehs_test::tally(label + " held-out z of " + effect, z_effect);
}

}  // namespace

// False failure (scripts/seed-study.sh 20, 24 Nov 2026; the code's rule: an effect is confirmed at
// a held-out z > 2 over 8 pieces, so a wrong effect is confirmed now and then by chance):
//  * jumps, per data set — inadequate in 20 of 20 (log10(smallest p / threshold) −30 … −108,
//    mean −66, sd 21); "outside the catalogue" needs < −6: P(miss) ≈ Φ(−2.9) ≈ 2e-3; the refits
//    of the wrongly significant suspects reach held-out z 0.10 ± 0.73 (max 1.49 of 16): a
//    confirmation (z > 2) ≈ Φ(−2.6) ≈ 5e-3. Both data sets must be inadequate; at least one of the
//    two must be fully right (no recommendation, outside the catalogue, heavy tails named):
//    P(both wrong) ≈ (7e-3)² ≈ 5e-5. A rule that confirms any wrong effect fails it.
//  * friction: coulomb_friction's held-out z 9.3 ± 1.5 (6.5 … 11.9) against the threshold 2,
//    P ≈ Φ(−4.9) ≈ 5e-7; it must come first (largest held-out gain). A look-alike is confirmed
//    beside it in 3 of 20 seeds (nonlinear_damping beyond coulomb_friction at z > 2 over 8
//    pieces): not checked, reported in bench/results/diagnose_calibration_log.md. Before the joint confirmation
//    (confirmation.hpp) this seed also recommended nonlinear_damping and velocity_dependent_noise.
// Cost ≈ 11 CPU s (three identify-vehs + diagnose-vehs runs of 64 000 samples).
TEST_CASE("diagnose-vehs outside the catalogue: impulsive excitation named as such, a hidden friction still named",
          "[diagnose][app][outside_catalogue]") {
  const bool verbose = std::getenv("VEHS_OC_VERBOSE") != nullptr;
  constexpr int records = 16, samples = 4000;
  constexpr double dt = 0.05;
  int fully_right = 0;
  for (const std::uint64_t seed : {11, 15}) {
    const fs::path dir = fresh_dir("vehs_outside_catalogue");
    Physics p;
    p.jump_rate = 0.1, p.jump_sd = 0.5;
    const std::string data = (dir / "jumps.csv").string();
    write_records(data, p, vehs_test::seed(seed), records, samples, dt);
    const nlohmann::json j = identify_and_diagnose(dir, data, vehs_test::seed(seed + 1));
    const std::string conclusion = j.value("conclusion", "");
    if (verbose) std::printf("jumps: %s\n", conclusion.c_str()), print_details(j);
    tally_diagnosis("jumps", j, "");
    const bool right = j["recommended"].empty() && j["outside_catalogue"] == true &&
                       conclusion.find("the misfit is outside the catalogue") != std::string::npos &&
                       conclusion.find("heavy-tailed innovations") != std::string::npos;
    vehs_test::tally("jumps outside the catalogue", right);
    CHECK(j["verdict"] == "inadequate");
    fully_right += right;
  }
  CHECK(fully_right >= 1);
  {
    const fs::path dir = fresh_dir("vehs_outside_catalogue_control");
    Physics p;
    p.mu = 0.2;
    const std::string data = (dir / "friction.csv").string();
    write_records(data, p, vehs_test::seed(13), records, samples, dt);
    const nlohmann::json j = identify_and_diagnose(dir, data, vehs_test::seed(14));
    const std::string conclusion = j.value("conclusion", "");
    if (verbose) std::printf("friction: %s\n", conclusion.c_str()), print_details(j);
    tally_diagnosis("friction", j, "coulomb_friction");
    vehs_test::tally("friction recommended", j["recommended"] == nlohmann::json::array({"coulomb_friction"}));
    CHECK(j["verdict"] == "inadequate");
    REQUIRE_FALSE(j["recommended"].empty());
    CHECK(j["recommended"][0] == "coulomb_friction");
    CHECK(j["outside_catalogue"] == false);
  }
}
