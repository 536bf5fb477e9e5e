// identify-vehs's figure of the fit against an independent truth: a driven Duffing oscillator in
// mm and s, sampled at 500 Hz with white sensor noise on x whose second difference alone would
// put the binned diffusion at several times the true a22. The record comes from this file's own
// stochastic Heun stepper (20 substeps per sample, the drive evaluated at every substep), not
// from vehs's simulator. The figure's data files (identify_fit_km_diffusion.csv and
// identify_fit_km_v.csv beside the SVG) must agree with the fitted model's curves
// (identify_fit_model.csv) bin by bin within the bins' error bars: the sensor noise removed from
// the diffusion, the input's term removed from the velocity bins.
//
// Error bars: a bin's se comes from 20 interleaved groups of blocks (19 degrees of freedom);
// with the model's own se, each of the m bins is one two-sided check at t_bound(m, 19): family-wise
// false failure ≤ 1e-4 (Bonferroni). Deterministic biases (O(h) discretisation at ωΔt = 0.1,
// bin centre vs bin mean) are below a tenth of the bins' se here.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

#include "stat_bounds.hpp"

namespace fs = std::filesystem;

namespace {

struct Rows {
  std::vector<std::vector<double>> rows;
};

Rows read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);  // header
  Rows r;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(cell.empty() ? std::nan("") : std::strtod(cell.c_str(), nullptr));
    r.rows.push_back(row);
  }
  return r;
}

/// Linear interpolation of column `col` against column `at` of the model curves.
double interpolate(const Rows& m, std::size_t at, std::size_t col, double where) {
  for (std::size_t i = 1; i < m.rows.size(); ++i)
    if (m.rows[i][at] >= where) {
      const auto& a = m.rows[i - 1];
      const auto& b = m.rows[i];
      const double w = (where - a[at]) / (b[at] - a[at]);
      return a[col] + w * (b[col] - a[col]);
    }
  return m.rows.back()[col];
}

// the rig: x in mm, t in s, u (base acceleration) in m/s²
constexpr double kK1 = 2500.0, kK3 = 300.0, kBeta = 5.0, kGamma = 800.0, kA22 = 2000.0;
constexpr double kDt = 0.002, kNoiseSd = 0.003;

/// The drive: 24 sines between 2 and 20 Hz with fixed random phases, rms about 1 m/s².
struct Drive {
  std::vector<double> f, phase;
  explicit Drive(std::mt19937_64& g) {
    std::uniform_real_distribution<double> ph(0.0, 2 * M_PI);
    for (int i = 0; i < 24; ++i) f.push_back(2.0 + 18.0 * i / 23.0), phase.push_back(ph(g));
  }
  double operator()(double t) const {
    double s = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) s += std::sin(2 * M_PI * f[i] * t + phase[i]);
    return s * std::sqrt(2.0 / static_cast<double>(f.size()));
  }
};

double b2(double x, double y, double u) { return -kK1 * x - kK3 * x * x * x - kBeta * y + kGamma * u; }

/// Writes t, x (with sensor noise), u; stochastic Heun (additive noise) with `sub` substeps.
void write_record(const fs::path& file, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> z(0.0, 1.0);
  const Drive drive(g);
  const int sub = 20;
  const double h = kDt / sub, sq = std::sqrt(kA22 * h);
  double x = 0.0, y = 0.0, t = 0.0;
  std::ofstream out(file);
  out << "t,x,u\n";
  out.precision(10);
  for (std::size_t i = 0; i < n; ++i) {
    out << i * kDt << ',' << x + kNoiseSd * z(g) << ',' << drive(i * kDt) << '\n';
    for (int s = 0; s < sub; ++s, t += h) {
      const double dw = sq * z(g);
      const double u0 = drive(t), u1 = drive(t + h);
      const double a0 = b2(x, y, u0);
      const double xp = x + y * h, yp = y + a0 * h + dw;
      const double a1 = b2(xp, yp, u1);
      x += 0.5 * (y + yp) * h;
      y += 0.5 * (a0 + a1) * h + dw;
    }
  }
}

}  // namespace

TEST_CASE("identify figure: binned diffusion without sensor noise and velocity bins without the input",
          "[tools][figure][long]") {
  const fs::path dir = fs::path(VEHS_BINARY_DIR) / "identify_figure_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_record(dir / "rig.csv", 300000, 77);
  std::ofstream(dir / "identify.json")
      << R"({"data": [")" << (dir / "rig.csv").string() << R"("], "output": ")" << (dir / "model.json").string()
      << R"(", "units": {"length": "mm", "time": "s", "input": "m/s^2"}, )"
      << R"("drift_library": ["x", "x^3", "y", "u"], "diffusion_library": ["1"], )"
      << R"("figures": ")" << (dir / "figures").string() << R"("})";
  const std::string cmd = (fs::path(VEHS_BINARY_DIR) / "identify-vehs").string() + " " +
                          (dir / "identify.json").string() + " -q > " + (dir / "out.txt").string() + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const Rows model = read_csv(dir / "figures" / "identify_fit_model.csv");
  const Rows diffusion = read_csv(dir / "figures" / "identify_fit_km_diffusion.csv");
  const Rows velocity = read_csv(dir / "figures" / "identify_fit_km_v.csv");
  REQUIRE(model.rows.size() > 100);
  // model columns: x, drift_x, drift_x_se, U, U_se, a22, a22_se, v, drift_v, drift_v_se
  struct Bin {
    const char* panel;
    double at, mean, se, model, model_se;
  };
  std::vector<Bin> bins;
  for (const auto& r : diffusion.rows)
    bins.push_back({"diffusion", r[0], r[1], r[2], interpolate(model, 0, 5, r[0]), interpolate(model, 0, 6, r[0])});
  for (const auto& r : velocity.rows)
    bins.push_back({"velocity", r[0], r[1], r[2], interpolate(model, 7, 8, r[0]), interpolate(model, 7, 9, r[0])});
  const int m = static_cast<int>(bins.size());
  REQUIRE(diffusion.rows.size() >= 30);  // the noise is removed, not every bin dropped
  REQUIRE(velocity.rows.size() >= 30);
  const double bound = vehs_test::t_bound(m, 19);
  double worst = 0.0;
  for (const auto& b : bins) {
    const double t = (b.mean - b.model) / std::hypot(b.se, b.model_se);
    worst = std::max(worst, std::abs(t));
    CAPTURE(b.panel, b.at, b.mean, b.se, b.model, b.model_se);
    CHECK(std::abs(t) <= bound);
  }
  std::printf("identify figure: %d bins, largest |t| %.2f (bound %.2f)\n", m, worst, bound);
}
