// Trajectory-steps per second of the simulator on the seed paper's model and scheme (degree-9
// penta-stable potential, multiplicative noise, rk4_euler = the paper's Eq. 30, Δt = 0.001,
// substeps 1, records of 10⁵ samples), next to a minimal hand-written loop doing the same
// arithmetic: the same Philox-4x32-10 + Box–Muller normals (fill_normals), the same batches of
// 8 records in SIMD lanes, RK4 on a hard-coded polynomial, Euler noise, x and y stored per
// sample — the practical ceiling, not a strawman. Both write into reused output buffers.
//
// Run (Release build):  build/bench/bench_simulate            (prints a summary table at the end)
//                       build/bench/bench_simulate --benchmark_filter=Paper
// Timings are wall-clock (UseRealTime) and noisy on a shared machine: the summary takes, for
// each benchmark, the best of its repetitions.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "vehs/core/app.hpp"
#include "vehs/core/model.hpp"
#include "vehs/sim/random.hpp"
#include "vehs/sim/simulate.hpp"

namespace {

using vehs::sim::CounterRng;
using vehs::sim::Purpose;

const vehs::Model& paper_model() {
  static const vehs::Model m = vehs::model_from_json(
      nlohmann::json::parse(R"({"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5,
                                          "x^9": -3.1, "y": -0.1},
                                "diffusion": {"1": 0.02, "x^2": 0.01}})"),
      "paper model");
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
constexpr int kL = 8;

void minimal_paper_loop(int records, std::vector<double>& X, std::vector<double>& Y) {
  const double k1 = 1.0, k3 = -7.7, k5 = 16.3, k7 = -12.5, k9 = 3.1, beta = 0.1;
  const double twoD = 0.02, twoQ = 0.01, h = kDt, sqh = std::sqrt(h);
  const CounterRng rng(1);
  const int batches = (records + kL - 1) / kL;
#pragma omp parallel for schedule(dynamic, 1)
  for (int b = 0; b < batches; ++b) {
    std::array<std::uint32_t, kL> ids;
    alignas(64) double x[kL], y[kL];
    const int active = std::min(kL, records - b * kL);
    for (int l = 0; l < kL; ++l) {
      ids[static_cast<std::size_t>(l)] = static_cast<std::uint32_t>(b * kL + (l < active ? l : 0));
      x[l] = -1.5 + 3.0 * rng.uniform(ids[static_cast<std::size_t>(l)], Purpose::Initial, 0);
      y[l] = 0.0;
    }
    alignas(64) double z[64 * kL];
    double* xo[kL];
    double* yo[kL];
    for (int l = 0; l < active; ++l) {
      xo[l] = X.data() + static_cast<std::size_t>(b * kL + l) * kSamples;
      yo[l] = Y.data() + static_cast<std::size_t>(b * kL + l) * kSamples;
      xo[l][0] = x[l];
      yo[l][0] = y[l];
    }
    for (std::size_t i = 1; i < kSamples; ++i) {
      const std::size_t n = i - 1;  // step index
      if (n % 64 == 0) vehs::sim::fill_normals<kL>(rng, ids, Purpose::Dynamics, n / 2, 32, z);
      const double* zi = z + (n % 64) * kL;
#pragma omp simd
      for (int l = 0; l < kL; ++l) {
        auto f = [&](double xx, double yy) {
          const double x2 = xx * xx;
          return -beta * yy - xx * (k1 + x2 * (k3 + x2 * (k5 + x2 * (k7 + x2 * k9))));
        };
        const double x0 = x[l], y0 = y[l];
        const double a1 = y0, b1 = f(x0, y0);
        const double a2 = y0 + 0.5 * h * b1, b2 = f(x0 + 0.5 * h * a1, y0 + 0.5 * h * b1);
        const double a3 = y0 + 0.5 * h * b2, b3 = f(x0 + 0.5 * h * a2, y0 + 0.5 * h * b2);
        const double a4 = y0 + h * b3, b4 = f(x0 + h * a3, y0 + h * b3);
        const double sigma = std::sqrt(twoD + twoQ * x0 * x0);
        x[l] = x0 + h / 6.0 * (a1 + 2.0 * (a2 + a3) + a4);
        y[l] = y0 + h / 6.0 * (b1 + 2.0 * (b2 + b3) + b4) + sigma * sqh * zi[l];
      }
      for (int l = 0; l < active; ++l) {
        xo[l][i] = x[l];
        yo[l][i] = y[l];
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
      double& best = best_[r.benchmark_name()];
      best = std::max(best, static_cast<double>(it->second));
    }
  }
  double best(const std::string& prefix) const {
    double b = 0.0;
    for (const auto& [name, rate] : best_)
      if (name.rfind(prefix, 0) == 0) b = std::max(b, rate);
    return b;
  }
  const std::map<std::string, double>& all() const { return best_; }

 private:
  std::map<std::string, double> best_;
};

}  // namespace

BENCHMARK(BM_Normals);
// args: threads, records, scheme
BENCHMARK(BM_PaperSimulate)
    ->Args({1, 100, kRk4})->Args({2, 100, kRk4})->Args({1, 128, kRk4})->Args({2, 128, kRk4})
    ->Args({1, 96, static_cast<int>(vehs::sim::Scheme::EulerMaruyama)})
    ->Args({1, 96, static_cast<int>(vehs::sim::Scheme::Baoab)})
    ->Args({1, 96, static_cast<int>(vehs::sim::Scheme::Taylor15)})
    ->ArgNames({"threads", "records", "scheme"})->UseRealTime()->Unit(benchmark::kMillisecond)
    ->Repetitions(3)->ReportAggregatesOnly(false);
BENCHMARK(BM_PaperMinimalLoop)
    ->Args({1, 100})->Args({2, 100})->Args({1, 128})->Args({2, 128})
    ->ArgNames({"threads", "records"})->UseRealTime()->Unit(benchmark::kMillisecond)
    ->Repetitions(3)->ReportAggregatesOnly(false);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  auto rate = [&](const std::string& name) { return reporter.best(name) / 1e6; };
  std::printf("\nSummary (best of repetitions; million trajectory-steps per second; rk4_euler, "
              "paper model, dt = 0.001, 1e5 samples/record, x and y stored):\n");
  std::printf("%-10s %14s %14s %14s %10s %10s\n", "records", "simulate 1T", "simulate 2T",
              "minimal 1T", "ratio 1T", "2T/1T");
  for (int records : {100, 128}) {
    const std::string r = std::to_string(records);
    const double s1 = rate("BM_PaperSimulate/threads:1/records:" + r + "/scheme:1");
    const double s2 = rate("BM_PaperSimulate/threads:2/records:" + r + "/scheme:1");
    const double m1 = rate("BM_PaperMinimalLoop/threads:1/records:" + r);
    if (s1 <= 0 && m1 <= 0) continue;
    std::printf("%-10d %14.1f %14.1f %14.1f %10.2f %10.2f\n", records, s1, s2, m1,
                m1 > 0 ? s1 / m1 : 0.0, s1 > 0 ? s2 / s1 : 0.0);
  }
  for (const auto& [name, best] : reporter.all()) std::printf("  %-60s %8.1f M/s\n", name.c_str(), best / 1e6);
  return 0;
}
