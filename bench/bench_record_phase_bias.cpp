// The shared forcing amplitude with one free phase per record: its incidental-parameter (Rice)
// bias and identify's first-order correction (include/vehs/likelihood/detail/record_phase_bias.hpp).
// Bistable Duffing x'' = x − x³ − 0.1y + A cos(0.8t + φ_r) + noise (2D 0.04), R records of N
// samples at Δt 0.35 (ω·Δt ≈ 0.5 in the wells), φ_r uniform, no sensor noise; every record
// simulated on its own random stream with its own phase. Per seed, two fits from the truth:
//   held — the true phases held (each record's t₀ moved by φ_r/ω, the shared phase fixed at 0);
//   free — refine with per_record_phase (what identify does), the amplitude corrected;
// and the free fit's uncorrected amplitude (corrected / factor). Prints the mean z of each and the
// paired shifts free − held in SE, beside the predicted R·SE/(2A).
//   OMP_NUM_THREADS=1 build/bench/bench_record_phase_bias R N SEEDS [A]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "vehs/core/parameters.hpp"
#include "vehs/likelihood/detail/record_phase_bias.hpp"
#include "vehs/likelihood/refine.hpp"
#include "vehs/sim/simulate.hpp"

using namespace vehs;

namespace {

Model truth_model(double A) {
  Model m;
  m.drift = {{Term::parse("x"), 1.0}, {Term::parse("x^3"), -1.0}, {Term::parse("y"), -0.1}};
  m.diffusion = {{Term::parse("1"), 0.04}};
  Effect e;
  e.id = EffectId::HarmonicForcing;
  e.params = {{"amplitude", A}, {"omega", 0.8}, {"phase", 0.0}};
  m.effects.push_back(e);
  return m;
}

Dataset records(const Model& truth, int R, std::size_t N, std::uint64_t seed, std::vector<double>& phases) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  Dataset d;
  phases.clear();
  for (int r = 0; r < R; ++r) {
    Model m = truth;
    phases.push_back(u(rng));
    m.effects[0].params["phase"] = phases.back();
    sim::SimulationOptions o;
    o.dt = 0.35;
    o.substeps = 35;
    o.records = 1;
    o.first_record = seed * 1000 + std::uint64_t(r);
    o.samples = N;
    o.seed = seed;
    o.record_y = false;
    d.append(sim::simulate(m, o));
  }
  return d;
}

struct Stat {
  double sum = 0, sum2 = 0;
  int n = 0;
  void add(double v) { sum += v, sum2 += v * v, ++n; }
  double mean() const { return sum / n; }
  double se() const { return n > 1 ? std::sqrt((sum2 - sum * sum / n) / (n - 1) / n) : NAN; }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: bench_record_phase_bias R N SEEDS [A]\n");
    return 2;
  }
  const int R = std::atoi(argv[1]), seeds = std::atoi(argv[3]);
  const std::size_t N = std::size_t(std::atol(argv[2]));
  const double A = argc > 4 ? std::atof(argv[4]) : 0.12, W = 0.8;
  const Model truth = truth_model(A);
  std::printf("# R %d records x %zu samples, dt 0.35, A %g, omega %g, no sensor noise; z of the amplitude\n", R, N, A, W);
  std::printf("%-5s %8s %8s %8s %8s %8s\n", "seed", "held", "free", "free_unc", "shift", "R.SE/2A");
  Stat held, free_c, free_u, shift_u, shift_c, predicted;
  for (int s = 0; s < seeds; ++s) {
    std::vector<double> ph;
    const Dataset d = records(truth, R, N, 7000 + std::uint64_t(s), ph);
    likelihood::RefineOptions o;
    o.estimate_measurement_noise = false;
    o.filter.threads = 1;
    Dataset shifted = d;
    for (std::size_t r = 0; r < d.records.size(); ++r) shifted.records[r].t0 += ph[r] / W;
    likelihood::RefineOptions oh = o;
    oh.fixed = {"harmonic_forcing.phase"};
    const auto rh = likelihood::refine({truth, 0.0, {}}, shifted, oh);
    likelihood::RefineOptions of = o;
    of.per_record_phase = true;
    const auto rf = likelihood::refine({truth, 0.0, ph}, d, of);
    const int ih = rh.find("harmonic_forcing.amplitude"), jf = rf.find("harmonic_forcing.amplitude");
    // the factor from the returned covariance (phases untouched by the correction)
    const double f = likelihood::detail::record_phase_amplitude_factor(rf);
    const double se = rf.stderrs[std::size_t(jf)] / f;
    const double zh = (rh.values[std::size_t(ih)] - A) / rh.stderrs[std::size_t(ih)];
    const double zc = (rf.values[std::size_t(jf)] - A) / se;
    const double zu = (rf.values[std::size_t(jf)] / f - A) / se;
    held.add(zh), free_c.add(zc), free_u.add(zu), shift_u.add(zu - zh), shift_c.add(zc - zh);
    predicted.add(R * se / (2.0 * rf.values[std::size_t(jf)] / f));
    std::printf("%-5d %+8.3f %+8.3f %+8.3f %+8.3f %8.3f\n", s, zh, zc, zu, zu - zh, predicted.sum / predicted.n);
    std::fflush(stdout);
  }
  std::printf("summary R %d: mean z held %+.3f +- %.3f, free corrected %+.3f +- %.3f, free uncorrected %+.3f +- %.3f;\n"
              "  paired free - held: uncorrected %+.3f +- %.3f SE (predicted R.SE/2A %.3f), corrected %+.3f +- %.3f SE\n",
              R, held.mean(), held.se(), free_c.mean(), free_c.se(), free_u.mean(), free_u.se(), shift_u.mean(),
              shift_u.se(), predicted.mean(), shift_c.mean(), shift_c.se());
  return 0;
}
