#pragma once
// Statistics shared by simulation (Monte Carlo), identification (residual checks) and
// diagnosis: means with standard errors that respect autocorrelation, histograms,
// autocorrelation functions and power spectra.
#include <cstddef>
#include <vector>

namespace vehs {

/// A mean and its standard error.
struct Estimate {
  double value = 0.0;
  double stderr_ = 0.0;
};

/// Mean of a (possibly autocorrelated) series with a batch-means standard error:
/// the series is cut into `batches` contiguous batches whose means are treated as
/// independent. Valid when a batch is much longer than the correlation time.
Estimate batch_mean(const double* v, std::size_t n, std::size_t batches = 32);

/// Combines per-group estimates (e.g. independent records) into one mean with a standard
/// error from the spread of the group values, weighting group i by weights[i] (e.g. its length).
/// With one group, its own standard error is returned.
Estimate combine_independent(const std::vector<Estimate>& groups, const std::vector<double>& weights);

/// Uniform-bin histogram over [lo, hi) with n bins; values outside are counted in `outside`.
struct Histogram1D {
  double lo = 0.0, hi = 1.0;
  std::vector<double> counts;
  double outside = 0.0;
  double total = 0.0;

  Histogram1D() = default;
  Histogram1D(double lo_, double hi_, std::size_t n) : lo(lo_), hi(hi_), counts(n, 0.0) {}
  void add(double v, double w = 1.0);
  void merge(const Histogram1D& o);
  double width() const { return (hi - lo) / static_cast<double>(counts.size()); }
  double center(std::size_t i) const { return lo + (static_cast<double>(i) + 0.5) * width(); }
  /// Density estimate (integrates to the fraction inside [lo, hi)).
  std::vector<double> density() const;
};

struct Histogram2D {
  double xlo = 0.0, xhi = 1.0, ylo = 0.0, yhi = 1.0;
  std::size_t nx = 0, ny = 0;
  std::vector<double> counts;  ///< row-major: counts[i * ny + j], i over x, j over y
  double outside = 0.0;
  double total = 0.0;

  Histogram2D() = default;
  Histogram2D(double xlo_, double xhi_, std::size_t nx_, double ylo_, double yhi_, std::size_t ny_)
      : xlo(xlo_), xhi(xhi_), ylo(ylo_), yhi(yhi_), nx(nx_), ny(ny_), counts(nx_ * ny_, 0.0) {}
  void add(double x, double y, double w = 1.0);
  void merge(const Histogram2D& o);
  std::vector<double> density() const;
};

/// Autocovariance-normalised autocorrelation ρ(0..max_lag) of a series (mean removed),
/// computed with an FFT in O(n log n).
std::vector<double> autocorrelation(const double* v, std::size_t n, std::size_t max_lag);

/// One-sided power spectral density by Welch's method (Hann window, 50 % overlap) with
/// `segment` samples per segment; frequencies in cycles per unit time.
struct Spectrum {
  std::vector<double> frequency;
  std::vector<double> density;
  std::size_t segments = 0;  ///< number of averaged segments (relative error ≈ 1/sqrt(segments))
};
Spectrum welch_spectrum(const double* v, std::size_t n, double dt, std::size_t segment);
/// Accumulates Welch spectra of several records (same dt and segment) into one average.
void accumulate_spectrum(Spectrum& total, const Spectrum& add);

/// Hellinger distance between two discrete densities on the same bins (cell areas equal):
/// H² = 1 − Σ sqrt(p q) / sqrt(Σp Σq).
double hellinger_distance(const std::vector<double>& p, const std::vector<double>& q);

}  // namespace vehs
