#include "vehs/core/diffusion_in_data.hpp"

#include <algorithm>
#include <limits>

namespace vehs {

DiffusionInData lowest_diffusion_in_data(const Model& model, const Dataset& data, int stride) {
  DiffusionInData out;
  out.a22 = std::numeric_limits<double>::infinity();
  const std::size_t k = static_cast<std::size_t>(std::max(stride, 1));
  for (std::size_t r = 0; r < data.records.size(); ++r) {
    const Record& rec = data.records[r];
    if (rec.size < 2 * k + 1) continue;
    const double* x = data.x_of(rec);
    const double* y = data.y_of(rec);
    const double inv = 1.0 / (2.0 * static_cast<double>(k) * rec.dt);
    for (std::size_t i = k; i + k < rec.size; ++i) {
      const double v = y ? y[i] : (x[i + k] - x[i - k]) * inv;
      const double a = model.a22(x[i], v);
      ++out.samples;
      if (a < 0.0) ++out.negative;
      if (a < out.a22) out.a22 = a, out.x = x[i], out.y = v, out.record = r, out.sample = i;
    }
  }
  if (out.samples == 0) out.a22 = 0.0;
  return out;
}

}  // namespace vehs
