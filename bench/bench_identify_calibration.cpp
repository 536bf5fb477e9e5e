// Calibration and accuracy of identification at the seed paper's data size, over independent
// datasets simulated with parameters the estimator never sees:
//
//   A. the paper's own scheme (Eq. 30, rk4_euler at the recorded step Δt = 0.001);
//   B–D. a sensor sampling a continuous process (rk4_euler with 50 substeps) at Δt = 0.01,
//        0.005 and 0.001.
//
// Why 50 substeps: with n internal steps whose noise enters Y in Euler fashion while X is
// integrated from the pre-noise velocities, the variance of the second difference of x exceeds
// the continuous-time value by exactly the factor 1 + 1/(2n²) (left/right Riemann sums of
// Brownian paths), i.e. +0.125 % at n = 20 — visible in 2D at 10⁷ samples. n = 50 makes it
// +0.02 %, a fifth of a standard error.
//
// Each dataset is `records` × `samples` (default 100 × 10⁵ = 10⁷ samples, the paper's size),
// identified with the default settings. Reported per case: mean (sd) of every parameter, the
// fraction of datasets with exactly the true support, the fraction of parameters within 5 % of
// the truth, and the coverage of the nominal 95 % intervals (target 88–99 %).
//
//   bench_identify_calibration [repeats=20] [records=100] [samples=100000] [cases=ABCD] [seed=0]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tools/terminal_progress.hpp"
#include "vehs/core/error.hpp"
#include "vehs/identify/study.hpp"

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 20;
  const int records = argc > 2 ? std::atoi(argv[2]) : 100;
  const std::size_t samples = argc > 3 ? static_cast<std::size_t>(std::atoll(argv[3])) : 100000;
  const std::string cases = argc > 4 ? argv[4] : "ABCD";
  const std::uint64_t seed = argc > 5 ? static_cast<std::uint64_t>(std::atoll(argv[5])) : 0;
  try {
    const vehs::Model truth = vehs::Model::paper(0.1, {{1, 1.0}, {3, -7.7}, {5, 16.3}, {7, -12.5}, {9, 3.1}}, 0.02, 0.01);
    struct Case {
      char id;
      const char* what;
      double dt;
      int substeps;
    };
    const Case all[] = {{'A', "paper's scheme (Eq. 30) at dt = 0.001", 0.001, 1},
                        {'B', "continuous process sampled at dt = 0.01", 0.01, 50},
                        {'C', "continuous process sampled at dt = 0.005", 0.005, 50},
                        {'D', "continuous process sampled at dt = 0.001", 0.001, 50}};
    long long covered = 0, intervals = 0;
    for (const Case& c : all) {
      if (cases.find(c.id) == std::string::npos) continue;
      vehs::identify::StudyOptions o;
      o.truth = truth;
      o.points = {{c.dt, samples}};
      o.repeats = repeats;
      o.records = records;
      o.substeps = c.substeps;
      o.seed = 1000 + static_cast<std::uint64_t>(c.id) + 100000 * seed;
      o.progress = vehs::tools::terminal_progress();
      const auto r = vehs::identify::run_study(o);
      const auto& p = r.points.front();
      std::printf("\n%c. %s: %d datasets of %d x %zu samples (simulate %.0f s, identify %.1f s in total)\n",
                  c.id, c.what, repeats, records, samples, p.seconds_simulate, p.seconds_identify);
      std::printf("%-8s %9s %12s %10s %12s %9s %9s\n", "param", "truth", "mean", "sd", "mean stderr",
                  "bias/sd", "cover95");
      for (const auto& s : p.parameters)
        std::printf("%-8s %9.4g %12.6g %10.3g %12.3g %+9.2f %8.0f%%\n", s.name.c_str(), s.truth, s.mean,
                    s.sd, s.mean_stderr, (s.mean - s.truth) / (s.sd / std::sqrt(repeats)), 100 * s.coverage);
      std::printf("exact support in %.0f%% of datasets; estimator: %s; coverage of nominal 95%% intervals "
                  "%.1f%% of %lld\n",
                  100 * p.support_exact, p.estimators_used.front().c_str(), 100 * r.coverage, r.intervals);
      covered += std::llround(r.coverage * static_cast<double>(r.intervals));
      intervals += r.intervals;
    }
    std::printf("\noverall coverage of the nominal 95%% intervals: %.1f%% of %lld (target 88-99%%)\n",
                100.0 * static_cast<double>(covered) / static_cast<double>(intervals), intervals);
    return 0;
  } catch (const vehs::Error& e) {
    std::fprintf(stderr, "bench_identify_calibration: error: %s\n", e.what());
    return 1;
  }
}
