#include "vehs/core/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>

#include <unsupported/Eigen/FFT>

#include "vehs/core/error.hpp"

namespace vehs {

Estimate batch_mean(const double* v, std::size_t n, std::size_t batches) {
  Estimate e;
  if (n == 0) return e;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += v[i];
  e.value = sum / static_cast<double>(n);
  batches = std::min(batches, n);
  if (batches < 2) return e;
  const std::size_t len = n / batches;
  double ss = 0.0;
  for (std::size_t b = 0; b < batches; ++b) {
    double m = 0.0;
    for (std::size_t i = b * len; i < (b + 1) * len; ++i) m += v[i];
    m /= static_cast<double>(len);
    ss += (m - e.value) * (m - e.value);
  }
  const double var_batch = ss / static_cast<double>(batches - 1);
  e.stderr_ = std::sqrt(var_batch / static_cast<double>(batches));
  return e;
}

Estimate combine_independent(const std::vector<Estimate>& groups, const std::vector<double>& weights) {
  require(groups.size() == weights.size() && !groups.empty(), "combine_independent: sizes differ");
  if (groups.size() == 1) return groups.front();
  const double wsum = std::accumulate(weights.begin(), weights.end(), 0.0);
  Estimate e;
  for (std::size_t i = 0; i < groups.size(); ++i) e.value += weights[i] * groups[i].value;
  e.value /= wsum;
  // variance of a weighted mean of independent groups, estimated from their spread
  double ss = 0.0, w2 = 0.0;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const double wi = weights[i] / wsum;
    ss += wi * wi * (groups[i].value - e.value) * (groups[i].value - e.value);
    w2 += wi * wi;
  }
  const double k = static_cast<double>(groups.size());
  e.stderr_ = std::sqrt(ss * k / (k - 1.0));
  (void)w2;
  return e;
}

void Histogram1D::add(double v, double w) {
  total += w;
  if (!(v >= lo && v < hi)) {
    outside += w;
    return;
  }
  auto i = static_cast<std::size_t>((v - lo) / width());
  if (i >= counts.size()) i = counts.size() - 1;
  counts[i] += w;
}

void Histogram1D::merge(const Histogram1D& o) {
  require(o.counts.size() == counts.size() && o.lo == lo && o.hi == hi, "histogram bins differ");
  for (std::size_t i = 0; i < counts.size(); ++i) counts[i] += o.counts[i];
  outside += o.outside;
  total += o.total;
}

std::vector<double> Histogram1D::density() const {
  std::vector<double> d(counts.size(), 0.0);
  if (total <= 0) return d;
  for (std::size_t i = 0; i < counts.size(); ++i) d[i] = counts[i] / (total * width());
  return d;
}

void Histogram2D::add(double x, double y, double w) {
  total += w;
  if (!(x >= xlo && x < xhi && y >= ylo && y < yhi)) {
    outside += w;
    return;
  }
  auto i = static_cast<std::size_t>((x - xlo) / (xhi - xlo) * static_cast<double>(nx));
  auto j = static_cast<std::size_t>((y - ylo) / (yhi - ylo) * static_cast<double>(ny));
  i = std::min(i, nx - 1);
  j = std::min(j, ny - 1);
  counts[i * ny + j] += w;
}

void Histogram2D::merge(const Histogram2D& o) {
  require(o.nx == nx && o.ny == ny && o.xlo == xlo && o.ylo == ylo, "histogram bins differ");
  for (std::size_t i = 0; i < counts.size(); ++i) counts[i] += o.counts[i];
  outside += o.outside;
  total += o.total;
}

std::vector<double> Histogram2D::density() const {
  std::vector<double> d(counts.size(), 0.0);
  if (total <= 0) return d;
  const double area = (xhi - xlo) / static_cast<double>(nx) * (yhi - ylo) / static_cast<double>(ny);
  for (std::size_t i = 0; i < counts.size(); ++i) d[i] = counts[i] / (total * area);
  return d;
}

namespace {
std::size_t next_pow2(std::size_t n) {
  std::size_t p = 1;
  while (p < n) p <<= 1;
  return p;
}
}  // namespace

std::vector<double> autocorrelation(const double* v, std::size_t n, std::size_t max_lag) {
  require(n >= 2, "autocorrelation needs at least 2 samples");
  max_lag = std::min(max_lag, n - 1);
  const double mean = std::accumulate(v, v + n, 0.0) / static_cast<double>(n);
  const std::size_t m = next_pow2(2 * n);
  std::vector<double> padded(m, 0.0);
  for (std::size_t i = 0; i < n; ++i) padded[i] = v[i] - mean;
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spec;
  fft.fwd(spec, padded);
  for (auto& c : spec) c = std::complex<double>(std::norm(c), 0.0);
  std::vector<double> acov;
  fft.inv(acov, spec);
  std::vector<double> rho(max_lag + 1, 0.0);
  if (acov[0] <= 0) return rho;
  for (std::size_t k = 0; k <= max_lag; ++k) rho[k] = acov[k] / acov[0];
  return rho;
}

Spectrum welch_spectrum(const double* v, std::size_t n, double dt, std::size_t segment) {
  require(segment >= 8 && segment <= n, "welch_spectrum: segment must be in [8, n]");
  Spectrum s;
  const std::size_t half = segment / 2;
  s.frequency.resize(half + 1);
  s.density.assign(half + 1, 0.0);
  for (std::size_t k = 0; k <= half; ++k)
    s.frequency[k] = static_cast<double>(k) / (static_cast<double>(segment) * dt);
  std::vector<double> window(segment);
  double wss = 0.0;
  for (std::size_t i = 0; i < segment; ++i) {
    window[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / static_cast<double>(segment));
    wss += window[i] * window[i];
  }
  Eigen::FFT<double> fft;
  std::vector<double> buf(segment);
  std::vector<std::complex<double>> out;
  for (std::size_t start = 0; start + segment <= n; start += half) {
    double mean = 0.0;
    for (std::size_t i = 0; i < segment; ++i) mean += v[start + i];
    mean /= static_cast<double>(segment);
    for (std::size_t i = 0; i < segment; ++i) buf[i] = (v[start + i] - mean) * window[i];
    fft.fwd(out, buf);
    for (std::size_t k = 0; k <= half; ++k) {
      const double scale = (k == 0 || k == half) ? 1.0 : 2.0;  // one-sided
      s.density[k] += scale * std::norm(out[k]) * dt / wss;
    }
    ++s.segments;
  }
  for (auto& d : s.density) d /= static_cast<double>(std::max<std::size_t>(s.segments, 1));
  return s;
}

void accumulate_spectrum(Spectrum& total, const Spectrum& add) {
  if (total.segments == 0) {
    total = add;
    return;
  }
  require(total.density.size() == add.density.size(), "spectra have different segment lengths");
  const double a = static_cast<double>(total.segments), b = static_cast<double>(add.segments);
  for (std::size_t k = 0; k < total.density.size(); ++k)
    total.density[k] = (a * total.density[k] + b * add.density[k]) / (a + b);
  total.segments += add.segments;
}

double hellinger_distance(const std::vector<double>& p, const std::vector<double>& q) {
  require(p.size() == q.size(), "hellinger_distance: sizes differ");
  double sp = 0.0, sq = 0.0, bc = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    sp += p[i];
    sq += q[i];
    bc += std::sqrt(std::max(p[i], 0.0) * std::max(q[i], 0.0));
  }
  if (sp <= 0 || sq <= 0) return 1.0;
  return std::sqrt(std::max(0.0, 1.0 - bc / std::sqrt(sp * sq)));
}

}  // namespace vehs
