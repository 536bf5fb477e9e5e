// Speed and memory of identification on the seed paper's data size: 100 records × 10⁵ samples
// (10⁷ samples, Δt = 0.001, the paper's scheme Eq. 30), read from the binary form (.npy) and
// from CSV, identified with the default settings.
//
//   bench_identify                      generate the files (once) and measure both, 1 thread
//   bench_identify generate DIR         write DIR/paper_1e7.npy and DIR/paper_1e7.csv
//   bench_identify run FILE [THREADS]   read + identify FILE in this process and report
//                                       wall times and the peak resident memory
//
// Targets (issue 4): ≤ 1 s from .npy and ≤ 3 s from CSV on one core; peak memory ≤ 1.5× the
// loaded displacement column (10⁷ doubles = 80 MB). Each measurement runs in its own process so
// that the peak memory is that of reading + identifying only.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "vehs/core/parallel.hpp"
#include "vehs/core/error.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/sim/simulate.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

double peak_rss_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // kB on Linux
}

vehs::Model paper_truth() {
  return vehs::Model::paper(0.1, {{1, 1.0}, {3, -7.7}, {5, 16.3}, {7, -12.5}, {9, 3.1}}, 0.02, 0.01);
}

int generate(const fs::path& dir) {
  fs::create_directories(dir);
  vehs::sim::SimulationOptions o;
  o.dt = 0.001;
  o.substeps = 1;
  o.records = 100;
  o.samples = 100000;
  o.seed = 2024;
  o.record_y = false;
  const auto t0 = Clock::now();
  const vehs::Dataset d = vehs::sim::simulate(paper_truth(), o);
  std::printf("simulated 10^7 samples in %.2f s\n", seconds_since(t0));
  for (const char* ext : {".npy", ".csv"}) {
    const fs::path p = dir / (std::string("paper_1e7") + ext);
    const auto t1 = Clock::now();
    vehs::write_measurements(p.string(), d, vehs::WriteColumns{false, false, 17});
    std::printf("wrote %s (%.0f MB) in %.2f s\n", p.c_str(), static_cast<double>(fs::file_size(p)) / 1e6,
                seconds_since(t1));
  }
  return 0;
}

int run(const std::string& file, int threads) {
  vehs::set_threads(threads);
  const double c0 = cpu_seconds();
  const auto t0 = Clock::now();
  vehs::ReadOptions ro;
  ro.read_u = false;
  const vehs::Dataset d = vehs::read_measurements(file, ro);
  const double t_read = seconds_since(t0);
  const double c1 = cpu_seconds();
  const auto t1 = Clock::now();
  const auto r = vehs::identify::identify(d, vehs::identify::Options{});
  const double t_id = seconds_since(t1);
  const double c2 = cpu_seconds();
  const double x_mb = static_cast<double>(d.x.size() * sizeof(double)) / (1024.0 * 1024.0);
  const double rss = peak_rss_mb();
  std::printf("%-34s threads %d  read %.3f s  identify %.3f s  total %.3f s  peak RSS %.0f MiB = %.2f x loaded x (%.0f MiB)\n",
              fs::path(file).filename().c_str(), threads, t_read, t_id, t_read + t_id, rss, rss / x_mb, x_mb);
  std::printf("    CPU time: read %.3f s, identify %.3f s, total %.3f s (wall times above include waiting "
              "for a core on a loaded machine)\n",
              c1 - c0, c2 - c1, c2 - c0);
  std::string timings;
  for (const auto& [stage, seconds] : r.report.fit.timings)
    timings += (timings.empty() ? "" : ", ") + stage + " " + std::to_string(seconds) + " s";
  std::printf("    estimator %s, %zu drift + %zu diffusion terms, timings %s\n",
              vehs::enum_to_string(vehs::kEstimatorNames, r.model.fit->estimator).c_str(), r.model.drift.size(),
              r.model.diffusion.size(), timings.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "generate" && argc > 2) return generate(argv[2]);
    if (mode == "run" && argc > 2) return run(argv[2], argc > 3 ? std::atoi(argv[3]) : 1);
    if (!mode.empty()) {
      std::fprintf(stderr, "usage: %s [generate DIR | run FILE [THREADS]]\n", argv[0]);
      return 2;
    }
    const fs::path dir = fs::path(argv[0]).parent_path() / "bench_identify_data";
    if (!fs::exists(dir / "paper_1e7.csv")) generate(dir);
    for (const char* f : {"paper_1e7.npy", "paper_1e7.csv"})
      for (int threads : {1, 2}) {
        const std::string cmd = std::string(argv[0]) + " run " + (dir / f).string() + " " + std::to_string(threads);
        if (std::system(cmd.c_str()) != 0) return 1;
      }
    return 0;
  } catch (const vehs::Error& e) {
    std::fprintf(stderr, "bench_identify: error: %s\n", e.what());
    return 1;
  }
}
