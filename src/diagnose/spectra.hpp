#pragma once
// Spectra and autocorrelations of the per-unit statistics (private). One FFT object per thread
// caches the plans; complex products use the limited-range rule (no NaN/inf recovery is needed
// for finite data), which keeps libgcc's slow __muldc3 out of the inner loops.
#include <cstddef>
#include <vector>

namespace vehs::diagnose::detail {

/// One-sided Welch density of v[0..n) (Hann window, segments of `seg` samples starting every
/// `hop` samples, each segment's mean removed), sampling interval dt; `out` gets seg/2 + 1 values
/// (left untouched when n < seg). Returns the number of segments.
std::size_t welch(const double* v, std::size_t n, double dt, std::size_t seg, std::size_t hop,
                  std::vector<double>& out);

/// Normalised autocorrelation ρ(0..max_lag) of v[0..n) (mean removed), by FFT.
void autocorrelation_fft(const double* v, std::size_t n, std::size_t max_lag, std::vector<double>& out);

/// Σ_j a[j]·a[j + l] for l = 0..max_lag (pairs within [0, n)), into sums[l] (vectorised).
void lag_products(const double* a, std::size_t n, std::size_t max_lag, double* sums);

}  // namespace vehs::diagnose::detail
