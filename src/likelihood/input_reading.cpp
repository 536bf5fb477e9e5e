// How a recorded input was applied between its samples, from its spectrum (input_reading.hpp).
#include "vehs/likelihood/input_reading.hpp"

#include <algorithm>
#include <cstdio>

#include "vehs/core/statistics.hpp"

namespace vehs::likelihood {

namespace {

constexpr std::size_t kSegment = 256;
constexpr std::size_t kShortest = 64;

std::string percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", 100.0 * share);
  return buf;
}

}  // namespace

InputReading read_input_interpolation(const Dataset& data) {
  InputReading out;
  if (!data.has_u()) {
    out.reason = "no input in the data";
    return out;
  }
  std::size_t segment = kSegment;  // one segment length for all: the shortest record's if shorter
  for (const Record& r : data.records)
    if (r.size >= kShortest) segment = std::min(segment, r.size & ~std::size_t(1));
  Spectrum total;
  for (const Record& r : data.records)
    if (r.size >= kShortest) accumulate_spectrum(total, welch_spectrum(data.u.data() + r.offset, r.size, r.dt, segment));
  double all = 0.0, high = 0.0;
  const std::size_t bins = total.density.size();
  for (std::size_t k = 1; k < bins; ++k) {
    all += total.density[k];
    if (4 * k > 3 * (bins - 1)) high += total.density[k];
  }
  if (!(all > 0.0)) {
    out.reason = "the input is constant or its records are shorter than " + std::to_string(kShortest) + " samples: zoh";
    return out;
  }
  out.high_band_share = high / all;
  if (out.high_band_share < kBandLimitedShare) {
    out.input = InputInterpolation::BandLimited;
    out.reason = percent(out.high_band_share) + " % of the input's power lies above 3/4 of the Nyquist frequency "
                 "(below " + percent(kBandLimitedShare) + " %): a band-limited signal that was sampled, band_limited";
  } else {
    out.reason = percent(out.high_band_share) + " % of the input's power lies above 3/4 of the Nyquist frequency: "
                 "power up to the Nyquist frequency, as a sequence held by a DAC, zoh";
  }
  return out;
}

}  // namespace vehs::likelihood
