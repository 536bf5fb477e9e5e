#include "vehs/likelihood/signals.hpp"

#include <cmath>
#include <random>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/input_path.hpp"

namespace vehs::likelihood {

std::vector<double> random_phase_multisine(std::size_t samples, double dt, int lines, double dw,
                                           double amplitude, std::uint64_t seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  std::vector<double> u(samples, 0.0);
  for (int j = 1; j <= lines; ++j) {
    const double w = dw * j, p = phase(g);
    for (std::size_t i = 0; i < samples; ++i)
      u[i] += amplitude * std::cos(w * dt * double(i) + p);  // physics-ok: a test signal, not an effect
  }
  return u;
}

Dataset slice_record(const Dataset& data, std::size_t record, std::size_t first, std::size_t last) {
  if (record >= data.records.size()) throw Error("slice: no record " + std::to_string(record));
  const Record& r = data.records[record];
  if (first >= last || last > r.size)
    throw Error("slice: samples [" + std::to_string(first) + ", " + std::to_string(last) +
                ") are outside record " + std::to_string(r.id) + " of " + r.source + " (" +
                std::to_string(r.size) + " samples)");
  Dataset d;
  Record s = r;
  s.offset = 0;
  s.size = last - first;
  s.first_line = r.first_line + first;
  s.t0 = r.t0 + double(first) * r.dt;
  d.records.push_back(s);
  d.x.assign(data.x_of(r) + first, data.x_of(r) + last);
  if (data.has_u()) d.u.assign(data.u_of(r) + first, data.u_of(r) + last);
  return d;
}

std::vector<double> refine_input(const std::vector<double>& u, int factor, InputInterpolation how) {
  if (factor < 1) throw Error("refine_input: factor must be >= 1");
  std::vector<double> out;
  if (u.size() < 2) return out;
  out.reserve((u.size() - 1) * std::size_t(factor));
  for (std::size_t k = 0; k + 1 < u.size(); ++k) {
    const detail::InputCubic c = detail::input_cubic(u.data(), u.size(), k, how);
    for (int j = 0; j < factor; ++j) {
      const double s = (j + 0.5) / factor;
      out.push_back(c[0] + s * (c[1] + s * (c[2] + s * c[3])));
    }
  }
  return out;
}

}  // namespace vehs::likelihood
