// The limited-range complex product must be in force where the FFT templates are instantiated.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("cx-limited-range")
#endif
#include "spectra.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include <unsupported/Eigen/FFT>

namespace vehs::diagnose::detail {

namespace {
Eigen::FFT<double>& thread_fft() {
  thread_local Eigen::FFT<double> fft;
  thread_local bool init = false;
  if (!init) {
    fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
    init = true;
  }
  return fft;
}
const std::vector<double>& hann(std::size_t n) {
  thread_local std::vector<double> w;
  if (w.size() != n) {
    w.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      w[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n));
  }
  return w;
}
}  // namespace

std::size_t welch(const double* v, std::size_t n, double dt, std::size_t seg, std::size_t hop,
                  std::vector<double>& out) {
  if (n < seg || seg < 8 || hop == 0) return 0;
  auto& fft = thread_fft();
  const auto& w = hann(seg);
  double wss = 0.0;
  for (double x : w) wss += x * x;
  const std::size_t half = seg / 2;
  out.assign(half + 1, 0.0);
  thread_local std::vector<double> buf;
  thread_local std::vector<std::complex<double>> spec;
  buf.resize(seg);
  spec.resize(half + 1);
  std::size_t count = 0;
  for (std::size_t start = 0; start + seg <= n; start += hop) {
    double mean = 0.0;
    for (std::size_t i = 0; i < seg; ++i) mean += v[start + i];
    mean /= static_cast<double>(seg);
    for (std::size_t i = 0; i < seg; ++i) buf[i] = (v[start + i] - mean) * w[i];
    fft.fwd(spec.data(), buf.data(), static_cast<Eigen::Index>(seg));
    for (std::size_t k = 0; k <= half; ++k) {
      const double scale = (k == 0 || k == half) ? 1.0 : 2.0;
      out[k] += scale * std::norm(spec[k]);
    }
    ++count;
  }
  const double norm = dt / (wss * static_cast<double>(count));
  for (auto& d : out) d *= norm;
  return count;
}

void autocorrelation_fft(const double* v, std::size_t n, std::size_t max_lag, std::vector<double>& out) {
  out.assign(max_lag + 1, 0.0);
  if (n < 2) return;
  std::size_t m = 1;
  while (m < 2 * n) m <<= 1;
  auto& fft = thread_fft();
  thread_local std::vector<double> buf;
  thread_local std::vector<std::complex<double>> spec;
  buf.assign(m, 0.0);
  double mean = 0.0;
  for (std::size_t i = 0; i < n; ++i) mean += v[i];
  mean /= static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) buf[i] = v[i] - mean;
  spec.resize(m / 2 + 1);
  fft.fwd(spec.data(), buf.data(), static_cast<Eigen::Index>(m));
  for (auto& c : spec) c = std::complex<double>(std::norm(c), 0.0);
  fft.inv(buf.data(), spec.data(), static_cast<Eigen::Index>(m));
  if (!(buf[0] > 0.0)) return;
  const std::size_t L = std::min(max_lag, n - 1);
  for (std::size_t k = 0; k <= L; ++k) out[k] = buf[k] / buf[0];
}

void lag_products(const double* a, std::size_t n, std::size_t max_lag, double* sums) {
  for (std::size_t l = 0; l <= max_lag; ++l) {
    if (l >= n) {
      sums[l] = 0.0;
      continue;
    }
    const std::size_t cnt = n - l;
    const double* b = a + l;
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    std::size_t j = 0;
    for (; j + 4 <= cnt; j += 4) {
      s0 += a[j] * b[j];
      s1 += a[j + 1] * b[j + 1];
      s2 += a[j + 2] * b[j + 2];
      s3 += a[j + 3] * b[j + 3];
    }
    for (; j < cnt; ++j) s0 += a[j] * b[j];
    sums[l] = (s0 + s1) + (s2 + s3);
  }
}

}  // namespace vehs::diagnose::detail
