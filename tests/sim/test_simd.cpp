// The SIMD levels of the simulator's kernels (vehs/sim/simd.hpp): every level this CPU can run
// gives bitwise the same normals, records and statistics as the scalar level on the same seeds
// (one source, lane-wise IEEE arithmetic, no fused multiply-add), for every scheme, on the fast
// path (the paper's polynomial family) and the general path, with burn-in, substeps and sensor
// noise. Deterministic: no statistical tolerance.
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/sim/random.hpp"
#include "vehs/sim/simd.hpp"
#include "vehs/sim/simulate.hpp"

using namespace vehs::sim;

namespace {

constexpr SimdLevel kAll[] = {SimdLevel::Scalar, SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512};

/// Restores the level in use when a test ends.
struct LevelGuard {
  SimdLevel saved = simd_level();
  ~LevelGuard() { set_simd_level(saved); }
};

template <class Values>  // std::vector<double> or vehs::Column
bool bitwise_equal(const Values& a, const Values& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

vehs::Model model_of(const std::string& json) {
  return vehs::model_from_json(nlohmann::json::parse(json), "test model");
}

// the paper's Eq. 30 model (fast path) and one with every kind of extra term (general path)
const char* kPaper = R"({"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
                         "diffusion": {"1": 0.02, "x^2": 0.01}})";
const char* kFriction = R"json({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.2, "sign(y)": -0.05, "x^2*y": -0.1},
                            "diffusion": {"1": 0.05, "y^2": 0.01}})json";

struct Run {
  vehs::Dataset data;
  MonteCarloStatistics stats;
};

Run run_at(SimdLevel level, const vehs::Model& m, Scheme scheme, double sensor_noise) {
  set_simd_level(level);
  SimulationOptions o;
  o.scheme = scheme;
  o.records = 13;  // a full batch of 8 and a padded one
  o.samples = 2000;
  o.dt = 0.002;
  o.substeps = 2;
  o.burn_in = 0.5;
  o.seed = 31;
  o.sensor_noise = sensor_noise;
  StatisticsOptions so;
  so.histograms = true;
  Run r;
  r.stats = simulate_statistics(m, o, so, nullptr, &r.data);
  return r;
}

}  // namespace

TEST_CASE("the SIMD level: names, the best level, bad levels are errors", "[simd]") {
  LevelGuard guard;
  CHECK(std::string(simd_level_name(SimdLevel::Avx2)) == "avx2");
  CHECK(simd_level_supported(SimdLevel::Scalar));
  CHECK(simd_level_supported(SimdLevel::Sse2));
  CHECK(simd_level_supported(best_simd_level()));
  for (SimdLevel l : kAll)
    if (!simd_level_supported(l)) CHECK_THROWS_AS(set_simd_level(l), vehs::Error);
  INFO("best level here: " << simd_level_name(best_simd_level()));
  SUCCEED();
}

TEST_CASE("normals are bitwise the same at every SIMD level and equal the scalar stream", "[simd]") {
  LevelGuard guard;
  const CounterRng rng(11);
  constexpr int L = 16;
  std::array<std::uint32_t, L> ids{};
  for (int l = 0; l < L; ++l) ids[static_cast<std::size_t>(l)] = static_cast<std::uint32_t>(7 * l + 3);
  const int pairs = 5000;
  std::vector<double> ref(static_cast<std::size_t>(2 * pairs * L));
  set_simd_level(SimdLevel::Scalar);
  fill_normals<L>(rng, ids, Purpose::Dynamics, 123456789, pairs, ref.data());
  for (SimdLevel l : kAll) {
    if (!simd_level_supported(l)) continue;
    set_simd_level(l);
    std::vector<double> v(ref.size());
    fill_normals<L>(rng, ids, Purpose::Dynamics, 123456789, pairs, v.data());
    INFO(simd_level_name(l));
    CHECK(bitwise_equal(v, ref));
  }
  // the scalar CounterRng does the same operations; bitwise unless this test's own compilation
  // fused its multiply-adds (a -march=native build with FMA)
  double worst = 0.0;
  for (int n = 0; n < 2 * pairs; n += 7)
    for (int l = 0; l < L; ++l) {
      const double s = rng.normal(ids[static_cast<std::size_t>(l)], Purpose::Dynamics,
                                  2 * 123456789ull + static_cast<std::uint64_t>(n));
      worst = std::max(worst, std::abs(s - ref[static_cast<std::size_t>(n * L + l)]));
    }
#if defined(__FMA__)
  CHECK(worst < 1e-14);
#else
  CHECK(worst == 0.0);
#endif
}

TEST_CASE("records and statistics are bitwise the same at every SIMD level", "[simd]") {
  LevelGuard guard;
  const auto paper = model_of(kPaper), friction = model_of(kFriction);
  for (const auto* m : {&paper, &friction})
    for (auto scheme : {Scheme::EulerMaruyama, Scheme::Rk4Euler, Scheme::Baoab, Scheme::Taylor15})
      for (double sensor : {0.0, 0.01}) {
        const Run ref = run_at(SimdLevel::Scalar, *m, scheme, sensor);
        for (SimdLevel l : kAll) {
          if (l == SimdLevel::Scalar || !simd_level_supported(l)) continue;
          const Run r = run_at(l, *m, scheme, sensor);
          INFO(simd_level_name(l) << ", scheme " << static_cast<int>(scheme) << (m == &paper ? ", paper" : ", friction")
                                  << ", sensor noise " << sensor);
          CHECK(bitwise_equal(r.data.x, ref.data.x));
          CHECK(bitwise_equal(r.data.y, ref.data.y));
          REQUIRE(r.stats.moments.size() == ref.stats.moments.size());
          for (std::size_t k = 0; k < ref.stats.moments.size(); ++k) {
            CHECK(std::memcmp(&r.stats.moments[k].second.value, &ref.stats.moments[k].second.value, sizeof(double)) == 0);
            CHECK(std::memcmp(&r.stats.moments[k].second.stderr_, &ref.stats.moments[k].second.stderr_, sizeof(double)) == 0);
          }
        }
      }
}
