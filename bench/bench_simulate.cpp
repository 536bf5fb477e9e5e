// Trajectory-steps per second of the simulator on the seed paper's model and scheme (degree-9
// penta-stable potential, multiplicative noise, rk4_euler = the paper's Eq. 30, Δt = 0.001,
// substeps 1, records of 10⁵ samples), next to a minimal hand-written loop doing the same
// arithmetic: the same Philox-4x32-10 + Box–Muller normals (fill_normals), the same batches of
// 8 records in SIMD lanes, RK4 on a hard-coded polynomial, Euler noise, x and y stored per
// sample — the practical ceiling, not a strawman. Both write into reused output buffers.
//
// Run (Release build):  build/bench/bench_simulate            (prints a summary table at the end)
//                       build/bench/bench_simulate --benchmark_filter=Paper
//                       VEHS_SIMD=avx2 build/bench/bench_simulate   (a given kernel level; every
//                       level the CPU runs: bench/simd_levels.sh)
// Timings are wall-clock (UseRealTime) and noisy on a shared machine: the summary takes, for
// each benchmark, the best of its repetitions.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "vehs/core/parallel.hpp"
#include "vehs/core/model.hpp"
#include "vehs/sim/random.hpp"
#include "vehs/sim/simd.hpp"
#include "vehs/sim/simulate.hpp"

namespace {

using vehs::sim::CounterRng;
using vehs::sim::Purpose;

const vehs::Model& paper_model() {
  static const vehs::Model m = vehs::Model::paper(0.1, {{1, 1.0}, {3, -7.7}, {5, 16.3}, {7, -12.5}, {9, 3.1}}, 0.02, 0.01);
  return m;
}

constexpr std::size_t kSamples = 100000;  // the paper: 10^5 samples of Δt = 0.001
constexpr double kDt = 0.001;

vehs::sim::SimulationOptions paper_options(int records, vehs::sim::Scheme scheme) {
  vehs::sim::SimulationOptions o;
  o.records = records;
  o.samples = kSamples;
  o.dt = kDt;
  o.substeps = 1;
  o.scheme = scheme;
  o.seed = 1;
  return o;
}

// ---- our path: vehs::sim::simulate ----------------------------------------------------------
void BM_PaperSimulate(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const int records = static_cast<int>(state.range(1));
  const auto scheme = static_cast<vehs::sim::Scheme>(state.range(2));
  vehs::set_threads(threads);
  const auto o = paper_options(records, scheme);
  vehs::Dataset out;
  vehs::sim::simulate(paper_model(), o, out);  // first touch of the output outside the timing
  for (auto _ : state) {
    vehs::sim::simulate(paper_model(), o, out);
    benchmark::DoNotOptimize(out.x.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(records) *
                          static_cast<long long>(kSamples - 1));
  vehs::set_threads(0);
}

// ---- the minimal hand-written loop ---------------------------------------------------------
// GCC vector extensions, 2 × 4 lanes of doubles kept in registers for the whole record, the
// polynomial's coefficients as compile-time constants: the fastest version we could write (an
// `#pragma omp simd` loop over lane arrays ran at about half this speed).
constexpr int kL = 8;
// (portable builds: GCC notes that 32-byte vectors cross ABI boundaries differently without AVX;
// these helpers are inline and file-local)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
typedef double v4d __attribute__((vector_size(32)));

inline v4d vsqrt(v4d a) {
#ifdef __AVX__
  return __builtin_ia32_sqrtpd256(a);
#else
  for (int i = 0; i < 4; ++i) a[i] = std::sqrt(a[i]);
  return a;
#endif
}

void minimal_paper_loop(int records, std::vector<double>& X, std::vector<double>& Y) {
  constexpr double k1 = 1.0, k3 = -7.7, k5 = 16.3, k7 = -12.5, k9 = 3.1, beta = 0.1;
  constexpr double twoD = 0.02, twoQ = 0.01, h = kDt;
  const double sqh = std::sqrt(h);
  const CounterRng rng(1);
  const int batches = (records + kL - 1) / kL;
#pragma omp parallel for schedule(dynamic, 1)
  for (int b = 0; b < batches; ++b) {
    std::array<std::uint32_t, kL> ids;
    alignas(64) double x0[kL];
    const int active = std::min(kL, records - b * kL);
    for (int l = 0; l < kL; ++l) {
      ids[static_cast<std::size_t>(l)] = static_cast<std::uint32_t>(b * kL + (l < active ? l : 0));
      x0[l] = -1.5 + 3.0 * rng.uniform(ids[static_cast<std::size_t>(l)], Purpose::Initial, 0);
    }
    v4d x[2], y[2];
    for (int g = 0; g < 2; ++g) {
      x[g] = v4d{x0[4 * g], x0[4 * g + 1], x0[4 * g + 2], x0[4 * g + 3]};
      y[g] = v4d{0.0, 0.0, 0.0, 0.0};
    }
    alignas(64) double z[64 * kL];
    double* xo[kL] = {};
    double* yo[kL] = {};
    for (int l = 0; l < active; ++l) {
      xo[l] = X.data() + static_cast<std::size_t>(b * kL + l) * kSamples;
      yo[l] = Y.data() + static_cast<std::size_t>(b * kL + l) * kSamples;
      xo[l][0] = x0[l];
      yo[l][0] = 0.0;
    }
    auto f = [](v4d xx, v4d yy) {
      const v4d x2 = xx * xx;
      return -beta * yy - xx * (k1 + x2 * (k3 + x2 * (k5 + x2 * (k7 + x2 * k9))));
    };
    for (std::size_t i = 1; i < kSamples; ++i) {
      const std::size_t n = i - 1;  // step index
      if (n % 64 == 0) vehs::sim::fill_normals<kL>(rng, ids, Purpose::Dynamics, n / 2, 32, z);
      const double* zi = z + (n % 64) * kL;
      for (int g = 0; g < 2; ++g) {
        v4d xi;
        std::memcpy(&xi, zi + 4 * g, sizeof xi);
        const v4d xx = x[g], yy = y[g];
        const v4d a1 = yy, b1 = f(xx, yy);
        const v4d a2 = yy + 0.5 * h * b1, b2 = f(xx + 0.5 * h * a1, yy + 0.5 * h * b1);
        const v4d a3 = yy + 0.5 * h * b2, b3 = f(xx + 0.5 * h * a2, yy + 0.5 * h * b2);
        const v4d a4 = yy + h * b3, b4 = f(xx + h * a3, yy + h * b3);
        const v4d sigma = vsqrt(twoD + twoQ * xx * xx);
        x[g] = xx + h / 6.0 * (a1 + 2.0 * (a2 + a3) + a4);
        y[g] = yy + h / 6.0 * (b1 + 2.0 * (b2 + b3) + b4) + sigma * sqh * xi;
      }
      if (active == kL) {
        for (int l = 0; l < kL; ++l) {
          xo[l][i] = x[l / 4][l % 4];
          yo[l][i] = y[l / 4][l % 4];
        }
      } else {
        for (int l = 0; l < active; ++l) {
          xo[l][i] = x[l / 4][l % 4];
          yo[l][i] = y[l / 4][l % 4];
        }
      }
    }
  }
}

void BM_PaperMinimalLoop(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const int records = static_cast<int>(state.range(1));
  vehs::set_threads(threads);
  std::vector<double> X(static_cast<std::size_t>(records) * kSamples), Y(X.size());
  minimal_paper_loop(records, X, Y);
  for (auto _ : state) {
    minimal_paper_loop(records, X, Y);
    benchmark::DoNotOptimize(X.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(records) *
                          static_cast<long long>(kSamples - 1));
  vehs::set_threads(0);
}

// ---- normals alone -----------------------------------------------------------------------------
void BM_Normals(benchmark::State& state) {
  const CounterRng rng(7);
  std::array<std::uint32_t, kL> ids{};
  for (int l = 0; l < kL; ++l) ids[static_cast<std::size_t>(l)] = static_cast<std::uint32_t>(l);
  alignas(64) double z[64 * kL];
  std::uint64_t pair = 0;
  for (auto _ : state) {
    vehs::sim::fill_normals<kL>(rng, ids, Purpose::Dynamics, pair, 32, z);
    pair += 32;
    benchmark::DoNotOptimize(z);
  }
  state.SetItemsProcessed(state.iterations() * 64 * kL);
}

constexpr int kRk4 = static_cast<int>(vehs::sim::Scheme::Rk4Euler);

// Summary: best rate of each benchmark over its repetitions.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const auto& r : runs) {
      if (r.run_type != Run::RT_Iteration) continue;
      auto it = r.counters.find("items_per_second");
      if (it == r.counters.end()) continue;
      const double wall_rate = static_cast<double>(it->second);
      double& best = best_[r.benchmark_name()];
      best = std::max(best, wall_rate);
      // per-core rate from the process CPU time (robust when other jobs share the machine)
      const double cpu = r.GetAdjustedCPUTime(), real = r.GetAdjustedRealTime();
      if (cpu > 0) {
        double& c = best_cpu_[r.benchmark_name()];
        c = std::max(c, wall_rate * real / cpu);
      }
    }
  }
  double best_cpu(const std::string& prefix) const {
    double b = 0.0;
    for (const auto& [name, rate] : best_cpu_)
      if (name.rfind(prefix, 0) == 0) b = std::max(b, rate);
    return b;
  }
  double best(const std::string& prefix) const {
    double b = 0.0;
    for (const auto& [name, rate] : best_)
      if (name.rfind(prefix, 0) == 0) b = std::max(b, rate);
    return b;
  }
  const std::map<std::string, double>& all() const { return best_; }

 private:
  std::map<std::string, double> best_, best_cpu_;
};

}  // namespace

BENCHMARK(BM_Normals);
// args: threads, records, scheme
BENCHMARK(BM_PaperSimulate)
    ->Args({1, 100, kRk4})->Args({2, 100, kRk4})->Args({1, 128, kRk4})->Args({2, 128, kRk4})
    ->Args({1, 96, static_cast<int>(vehs::sim::Scheme::EulerMaruyama)})
    ->Args({1, 96, static_cast<int>(vehs::sim::Scheme::Baoab)})
    ->Args({1, 96, static_cast<int>(vehs::sim::Scheme::Taylor15)})
    ->ArgNames({"threads", "records", "scheme"})->UseRealTime()->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond)->Repetitions(3)->ReportAggregatesOnly(false);
BENCHMARK(BM_PaperMinimalLoop)
    ->Args({1, 100})->Args({2, 100})->Args({1, 128})->Args({2, 128})
    ->ArgNames({"threads", "records"})->UseRealTime()->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond)->Repetitions(3)->ReportAggregatesOnly(false);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  auto rate = [&](const std::string& name) { return reporter.best(name) / 1e6; };
  auto per_core = [&](const std::string& name) { return reporter.best_cpu(name) / 1e6; };
  std::printf("\nSIMD level of the simulator's kernels: %s (VEHS_SIMD to force one; the minimal loop is\n"
              "compiled for the build's own flags)\n", vehs::sim::simd_level_name(vehs::sim::simd_level()));
  std::printf("\nSummary, best of repetitions, million trajectory-steps per second (rk4_euler, paper model,\n"
              "dt = 0.001, 1e5 samples per record, x and y stored). 'wall' = steps / elapsed time,\n"
              "'per core' = steps / process CPU time (meaningful when other jobs share the cores):\n");
  std::printf("%-8s %12s %12s %12s %12s %12s %10s %10s\n", "records", "sim 1T wall", "sim 2T wall",
              "min 1T wall", "sim per core", "min per core", "ratio", "2T/1T");
  for (int records : {100, 128}) {
    const std::string r = std::to_string(records);
    const std::string s1 = "BM_PaperSimulate/threads:1/records:" + r + "/scheme:1";
    const std::string s2 = "BM_PaperSimulate/threads:2/records:" + r + "/scheme:1";
    const std::string m1 = "BM_PaperMinimalLoop/threads:1/records:" + r;
    if (rate(s1) <= 0 && rate(m1) <= 0) continue;
    std::printf("%-8d %12.1f %12.1f %12.1f %12.1f %12.1f %10.2f %10.2f\n", records, rate(s1), rate(s2), rate(m1),
                per_core(s1), per_core(m1), per_core(m1) > 0 ? per_core(s1) / per_core(m1) : 0.0,
                rate(s1) > 0 ? rate(s2) / rate(s1) : 0.0);
  }
  std::printf("\nAll benchmarks (best wall rate, best per-core rate, M/s):\n");
  for (const auto& [name, best] : reporter.all())
    std::printf("  %-60s %8.1f %8.1f\n", name.c_str(), best / 1e6, per_core(name));
  return 0;
}
