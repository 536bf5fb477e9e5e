#pragma once
// Philox-4x32-10 + Box–Muller on 8 lanes (8 records), for every instruction-set level from one
// source: the same operations, in the same order, as the scalar CounterRng::normal_pair of
// vehs/sim/random.hpp (whose series, log_of_parts and quarter_sin_cos, it shares), without fused
// multiply-adds, so each lane's numbers are bitwise those of the scalar stream.
#include <cstddef>
#include <cstdint>

#include "simd/lanes.hpp"
#include "vehs/sim/random.hpp"

namespace vehs::sim::VEHS_SIMD_NS {

/// Philox words of 8 lanes, one 32-bit word in the low half of each 64-bit lane.
struct PhiloxWords {
  U64 w0, w1, w2, w3;
};

VEHS_LANE_INLINE PhiloxWords philox(std::uint32_t key0, std::uint32_t key1, const U64& records,
                                    std::uint32_t purpose, std::uint64_t index) {
  // The rounds work on the pieces of the words directly (not on whole U64 values): GCC rebuilt
  // the assigned U64s of a 2-piece (AVX2) state through 16-byte stack stores that the next
  // round's 32-byte loads could not forward from, which made AVX2 2× slower than SSE2.
  const PU m0 = broadcast<PU>(std::uint64_t{Philox4x32::kMul0}), m1 = broadcast<PU>(std::uint64_t{Philox4x32::kMul1});
  const PU lo32 = broadcast<PU>(std::uint64_t{0xFFFFFFFFu});
  PU w0[kPieces], w1[kPieces], w2[kPieces], w3[kPieces];
  for (int i = 0; i < kPieces; ++i) {
    w0[i] = broadcast<PU>(index & 0xFFFFFFFFu);
    w1[i] = broadcast<PU>(index >> 32);
    w2[i] = records.p[i];
    w3[i] = broadcast<PU>(std::uint64_t{purpose});
  }
  std::uint32_t k0 = key0, k1 = key1;
  for (int round = 0; round < 10; ++round) {
    const PU key_a = broadcast<PU>(std::uint64_t{k0}), key_b = broadcast<PU>(std::uint64_t{k1});
    for (int i = 0; i < kPieces; ++i) {
      const PU p0 = piece_mul_lo32(w0[i], m0), p1 = piece_mul_lo32(w2[i], m1);
      const PU n0 = (p1 >> 32) ^ w1[i] ^ key_a;
      const PU n2 = (p0 >> 32) ^ w3[i] ^ key_b;
      w1[i] = p1 & lo32;
      w3[i] = p0 & lo32;
      w0[i] = n0;
      w2[i] = n2;
    }
    k0 += Philox4x32::kWeyl0;
    k1 += Philox4x32::kWeyl1;
  }
  PhiloxWords c;
  for (int i = 0; i < kPieces; ++i) {
    c.w0.p[i] = w0[i];
    c.w1.p[i] = w1[i];
    c.w2.p[i] = w2[i];
    c.w3.p[i] = w3[i];
  }
  return c;
}

/// detail::log_unit on lanes.
VEHS_LANE_INLINE F64 log_unit(const F64& u) {
  const U64 bits = bits_of(u);
  // the exponent field (≤ 1023 here) as a double, exactly: OR-ed into the mantissa of 2^52
  F64 e = double_of((bits >> 52) | splat(std::uint64_t{0x4330000000000000ull})) - splat(0x1p52 + 1023.0);
  F64 m = double_of((bits & splat(std::uint64_t{0xFFFFFFFFFFFFFull})) | splat(std::uint64_t{0x3FFull} << 52));
  const I64 big = m > splat(1.4142135623730951);
  m = blend(big, m * 0.5, m);
  e = blend(big, e + 1.0, e);
  return detail::log_of_parts(e, m);
}

/// The two normals of one Philox block per lane (detail::unit_circle_point and the radius).
VEHS_LANE_INLINE void box_muller(const PhiloxWords& w, F64& cos_out, F64& sin_out) {
  const U64 exponent = splat(std::uint64_t{0x3FFull} << 52);
  const U64 mantissa = splat(std::uint64_t{0xFFFFFFFFFFFFFull});
  // radius from words 0-1: u = k·2⁻⁵² + 2⁻⁵³
  const U64 rb = (w.w0 << 20) | (w.w1 >> 12);
  const F64 u1 = (double_of(rb | exponent) - 1.0) + 0x1p-53;
  const F64 radius = sqrt_lanes(-2.0 * log_unit(u1));
  // angle from words 2-3: quarter turn from the top 2 of the 52 bits, φ ∈ [−π/4, π/4) from the rest
  const U64 ab = (w.w2 << 20) | (w.w3 >> 12);
  const F64 r = double_of(exponent | ((ab << 2) & mantissa));
  const F64 phi = (r - 1.5) * 1.5707963267948966;
  F64 sp, cp;
  detail::quarter_sin_cos(phi, sp, cp);
  const I64 odd = bit_set(ab, 50), neg = bit_set(ab, 51);
  const F64 cq = blend(odd, -sp, cp), sq = blend(odd, cp, sp);
  cos_out = radius * blend(neg, -cq, cq);
  sin_out = radius * blend(neg, -sq, sq);
}

/// The normals of 8 records: normal n of lane l at out[n·stride + l].
inline void fill_normals8(std::uint32_t key0, std::uint32_t key1, const std::uint32_t* records,
                          std::uint32_t purpose, std::uint64_t first_pair, int pairs, double* out,
                          std::size_t stride) {
  std::uint64_t wide[kL];
  for (int l = 0; l < kL; ++l) wide[l] = records[l];
  U64 rec;
  std::memcpy(&rec, wide, sizeof rec);
  for (int p = 0; p < pairs; ++p) {
    const PhiloxWords w = philox(key0, key1, rec, purpose, first_pair + static_cast<std::uint64_t>(p));
    F64 c, s;
    box_muller(w, c, s);
    Lanes{c}.store(out + static_cast<std::size_t>(2 * p) * stride);
    Lanes{s}.store(out + static_cast<std::size_t>(2 * p + 1) * stride);
  }
}

}  // namespace vehs::sim::VEHS_SIMD_NS
