#pragma once
// The fast path of the simulator on lanes: PolynomialSystem (the paper's polynomial family) with
// any stepper of vehs/sim/steppers.hpp, 8 records in lockstep, normals generated 64 steps at a
// time — the same system and stepper templates as everywhere else, instantiated on the lane type
// of this instruction-set level (simd/lanes.hpp).
#include <cstddef>
#include <cstdint>

#include "simd/kernel_table.hpp"
#include "simd/lanes.hpp"
#include "simd/normals.hpp"
#include "vehs/sim/detail/model_system.hpp"
#include "vehs/sim/steppers.hpp"

namespace vehs::sim::VEHS_SIMD_NS {

/// Refills the batch's normals: the next kBlock steps of M normals per lane.
template <int M>
__attribute__((noinline)) void refill_normals(detail::FastBatch& b) {
  constexpr int pairs = detail::FastBatch::kBlock * M / 2;
  fill_normals8(b.key0, b.key1, b.records, static_cast<std::uint32_t>(Purpose::Dynamics), b.next_pair, pairs,
                b.normals, kL);
  b.next_pair += pairs;
}

template <class Stepper, int K>
__attribute__((flatten)) std::size_t advance_k(const detail::FastRun& run, detail::FastBatch& b,
                                               std::size_t intervals, double* out) {
  using System = detail::PolynomialSystem<kL, K, LaneTypes>;
  constexpr int M = Stepper::normals_per_source;
  const System sys(*run.fast);
  const Stepper stepper{};
  LaneTypes::State s;
  s.col(0) = Lanes::load(b.x);
  s.col(1) = Lanes::load(b.y);
  int cursor = b.cursor;
  const double h = run.h, lim = run.bound;
  const int substeps = run.substeps;
  std::size_t n = 0;
  for (; n < intervals; ++n) {
    for (int j = 0; j < substeps; ++j) {
      if (cursor == detail::FastBatch::kBlock) {
        refill_normals<M>(b);
        cursor = 0;
      }
      // the fast systems do not depend on time
      stepper.step(sys, s, 0.0, h, Normals{b.normals + cursor * M * kL});
      ++cursor;
    }
    if (!(s.col(0).abs() <= lim).all() || !(s.col(1).abs() <= lim).all()) break;
    if (out) {
      s.col(0).store(out + 2 * kL * n);
      s.col(1).store(out + 2 * kL * n + kL);
    }
  }
  s.col(0).store(b.x);
  s.col(1).store(b.y);
  b.cursor = cursor;
  return n;
}

/// PolynomialSystem<K> for the model's K (a linear restoring force runs with K = 2).
template <class Stepper>
std::size_t advance(const detail::FastRun& run, detail::FastBatch& b, std::size_t intervals, double* out) {
  switch (run.fast->k) {
    case 1:
    case 2: return advance_k<Stepper, 2>(run, b, intervals, out);
    case 3: return advance_k<Stepper, 3>(run, b, intervals, out);
    case 4: return advance_k<Stepper, 4>(run, b, intervals, out);
    case 5: return advance_k<Stepper, 5>(run, b, intervals, out);
    default: return advance_k<Stepper, 6>(run, b, intervals, out);
  }
}

}  // namespace vehs::sim::VEHS_SIMD_NS
