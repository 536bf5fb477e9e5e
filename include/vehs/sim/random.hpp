#pragma once
// Counter-based random numbers for reproducible, thread-count-independent simulation.
//
// * Generator: Philox-4x32-10 (Salmon, Moraes, Dror, Shaw, "Parallel random numbers: as easy
//   as 1, 2, 3", SC'11), written from the published description: a keyed bijection of a
//   128-bit counter, 10 rounds of two 32×32→64-bit multiplications. Checked against the
//   Random123 known-answer vectors in tests/sim/test_random.cpp.
// * Streams: key = the 64-bit seed; counter = (index_lo, index_hi, record, purpose). A record's
//   random numbers therefore depend only on (seed, record, purpose, index) — never on the
//   thread count or on how records are batched into SIMD lanes.
// * Uniforms: 52 random mantissa bits, u = k·2⁻⁵² + 2⁻⁵³ ∈ (0, 1) (never 0 or 1), built by
//   bit manipulation so that it vectorises (AVX2 has no 64-bit integer → double conversion).
// * Normals: Box–Muller on one Philox block: radius sqrt(−2 ln u₁) from words 0–1 (52 bits;
//   the largest attainable |z| is sqrt(2·53·ln 2) ≈ 8.57, P(|Z| > 8.57) ≈ 1e-17), angle from
//   words 2–3 (52 bits). The angle's sine and cosine are evaluated in double precision by
//   Taylor polynomials on a quarter turn φ ∈ [−π/4, π/4) (truncation error < 3e-14) followed
//   by an exact quarter-turn rotation chosen by the two top bits — vectorisable with selects.
//   ln u₁ uses our own atanh-series logarithm (detail::log_unit, relative error < 1e-14),
//   about twice as fast as Eigen's generic plog on AVX2 because it knows u₁ ∈ (0, 1].
//   Each block gives two independent N(0, 1) values. fill_normals computes them for 8 records at
//   once with the vector kernel of the SIMD level in use (src/sim/simd/normals.hpp: the same
//   operations in the same order, no fused multiply-add, so the same bits at every level).
//   Moments, tails and a Kolmogorov–Smirnov test are in tests/sim/test_random.cpp.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <cstddef>

namespace vehs::sim {

/// What a stream of random numbers is used for (word 3 of the Philox counter), so that, e.g.,
/// switching on sensor noise does not change the simulated path.
enum class Purpose : std::uint32_t {
  Dynamics = 0,      ///< Wiener increments of the integration steps
  Initial = 1,       ///< initial conditions (x0, y0, hidden states)
  SensorNoise = 2,   ///< white noise on the recorded x
  User = 3,          ///< free for tests and tools
};

struct Philox4x32 {
  using Block = std::array<std::uint32_t, 4>;
  static constexpr std::uint32_t kMul0 = 0xD2511F53u, kMul1 = 0xCD9E8D57u;
  static constexpr std::uint32_t kWeyl0 = 0x9E3779B9u, kWeyl1 = 0xBB67AE85u;

  /// Philox-4x32-10 of `counter` under `key` (10 rounds, key bumped between rounds).
  static Block hash(Block c, std::uint32_t k0, std::uint32_t k1) {
    for (int round = 0; round < 10; ++round) {
      const std::uint64_t p0 = std::uint64_t{kMul0} * c[0];
      const std::uint64_t p1 = std::uint64_t{kMul1} * c[2];
      c = {static_cast<std::uint32_t>(p1 >> 32) ^ c[1] ^ k0, static_cast<std::uint32_t>(p1),
           static_cast<std::uint32_t>(p0 >> 32) ^ c[3] ^ k1, static_cast<std::uint32_t>(p0)};
      k0 += kWeyl0;
      k1 += kWeyl1;
    }
    return c;
  }
};

namespace detail {

/// (0, 1) uniform from two words: 52 mantissa bits, offset by half an ulp of the grid.
inline double uniform_from_words(std::uint32_t hi, std::uint32_t lo) {
  const std::uint64_t bits = (std::uint64_t{0x3FF} << 52) |
                             (((std::uint64_t{hi} << 32) | lo) >> 12);
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return (d - 1.0) + 0x1p-53;
}

// The arithmetic of the normals, written once for doubles and for the simulator's SIMD lanes
// (src/sim/simd/normals.hpp instantiates these templates on its lane type): the same
// operations in the same order, so every path gives the same bits.
#if defined(__GNUC__)
#define VEHS_RNG_INLINE inline __attribute__((always_inline))
#else
#define VEHS_RNG_INLINE inline
#endif

/// sin φ and cos φ on |φ| ≤ π/4 by their Taylor series (the first omitted terms are < 3e-14 and
/// < 1e-15), Horner's rule in φ².
template <class V>
VEHS_RNG_INLINE void quarter_sin_cos(const V& phi, V& sp, V& cp) {
  const V p2 = phi * phi;
  V t = -1.0 / 39916800 + p2 * (1.0 / 6227020800.0);
  t = 1.0 / 362880 + p2 * t;
  t = -1.0 / 5040 + p2 * t;
  t = 1.0 / 120 + p2 * t;
  t = -1.0 / 6 + p2 * t;
  sp = phi * (1.0 + p2 * t);
  V c = 1.0 / 479001600.0 + p2 * (-1.0 / 87178291200.0);
  c = -1.0 / 3628800 + p2 * c;
  c = 1.0 / 40320 + p2 * c;
  c = -1.0 / 720 + p2 * c;
  c = 1.0 / 24 + p2 * c;
  c = -0.5 + p2 * c;
  cp = 1.0 + p2 * c;
}

/// e·ln 2 + ln m for m ∈ [√½, √2): ln m = 2·atanh(s), s = (m−1)/(m+1), |s| ≤ 0.1716, series to
/// s^17 (truncation < 4e-16 absolute).
template <class V>
VEHS_RNG_INLINE V log_of_parts(const V& e, const V& m) {
  const V sv = (m - 1.0) / (m + 1.0);
  const V s2 = sv * sv;
  V q = (2.0 / 17) * s2 + 2.0 / 15;
  q = q * s2 + 2.0 / 13;
  q = q * s2 + 2.0 / 11;
  q = q * s2 + 2.0 / 9;
  q = q * s2 + 2.0 / 7;
  q = q * s2 + 2.0 / 5;
  q = q * s2 + 2.0 / 3;
  q = q * s2 + 2.0;
  return e * 0.6931471805599453 + sv * q;
}

/// sin and cos of the angle 2π·a where `bits` holds a in its 52 low bits (a ∈ [0, 1)):
/// the top 2 of the 52 bits pick the quarter turn, the other 50 the offset φ ∈ [−π/4, π/4).
inline void unit_circle_point(std::uint64_t bits52, double& c, double& s) {
  const std::uint64_t quadrant = bits52 >> 50;
  const std::uint64_t rest = (std::uint64_t{0x3FF} << 52) | ((bits52 << 2) & 0xFFFFFFFFFFFFFull);
  double r;
  std::memcpy(&r, &rest, sizeof r);
  const double phi = (r - 1.5) * 1.5707963267948966;  // [−π/4, π/4)
  double sp, cp;
  quarter_sin_cos(phi, sp, cp);
  // rotate by quadrant·π/2
  const bool odd = quadrant & 1u, neg = quadrant & 2u;
  const double cq = odd ? -sp : cp, sq = odd ? cp : sp;
  c = neg ? -cq : cq;
  s = neg ? -sq : sq;
}

/// ln(u) for u in (0, 1] (the Box–Muller radius): u = 2^e·m with m ∈ [√½, √2), then
/// log_of_parts. Relative error vs std::log is tested to be < 1e-14 over (0, 1].
inline double log_unit(double u) {
  std::uint64_t bits;
  std::memcpy(&bits, &u, sizeof bits);
  double e = static_cast<double>(static_cast<int>(bits >> 52) - 1023);
  std::uint64_t mbits = (bits & 0xFFFFFFFFFFFFFull) | (std::uint64_t{0x3FF} << 52);
  double m;
  std::memcpy(&m, &mbits, sizeof m);
  if (m > 1.4142135623730951) {
    m *= 0.5;
    e += 1.0;
  }
  return log_of_parts(e, m);
}

}  // namespace detail

/// Scalar access to the streams (tests, initial conditions, sensor noise).
class CounterRng {
 public:
  explicit CounterRng(std::uint64_t seed)
      : k0_(static_cast<std::uint32_t>(seed)), k1_(static_cast<std::uint32_t>(seed >> 32)) {}

  Philox4x32::Block block(std::uint64_t record, Purpose purpose, std::uint64_t index) const {
    return Philox4x32::hash({static_cast<std::uint32_t>(index),
                             static_cast<std::uint32_t>(index >> 32),
                             static_cast<std::uint32_t>(record),
                             static_cast<std::uint32_t>(purpose)},
                            k0_, k1_);
  }
  /// Uniform in (0, 1): the first 52 bits of block `index`.
  double uniform(std::uint64_t record, Purpose purpose, std::uint64_t index) const {
    const auto b = block(record, purpose, index);
    return detail::uniform_from_words(b[0], b[1]);
  }
  /// The pair of independent standard normals of block `index`.
  std::array<double, 2> normal_pair(std::uint64_t record, Purpose purpose,
                                    std::uint64_t index) const {
    const auto b = block(record, purpose, index);
    const double u1 = detail::uniform_from_words(b[0], b[1]);
    const double radius = std::sqrt(-2.0 * detail::log_unit(u1));
    double c, s;
    detail::unit_circle_point(((std::uint64_t{b[2]} << 32) | b[3]) >> 12, c, s);
    return {radius * c, radius * s};
  }
  /// Normal number n of a stream (= component n % 2 of pair n / 2).
  double normal(std::uint64_t record, Purpose purpose, std::uint64_t n) const {
    return normal_pair(record, purpose, n / 2)[n % 2];
  }
  std::uint32_t key0() const { return k0_; }
  std::uint32_t key1() const { return k1_; }

 private:
  std::uint32_t k0_, k1_;
};

namespace detail {
/// Normal pairs of instances (pair index, record) — the portable path.
inline void normal_pairs_portable(const CounterRng& rng, const std::uint32_t* records, int lanes,
                                  Purpose purpose, std::uint64_t first_pair, int pairs,
                                  double* out) {
  for (int p = 0; p < pairs; ++p)
    for (int l = 0; l < lanes; ++l) {
      const auto z = rng.normal_pair(records[l], purpose, first_pair + static_cast<std::uint64_t>(p));
      out[static_cast<std::size_t>(2 * p) * static_cast<std::size_t>(lanes) + static_cast<std::size_t>(l)] = z[0];
      out[static_cast<std::size_t>(2 * p + 1) * static_cast<std::size_t>(lanes) + static_cast<std::size_t>(l)] = z[1];
    }
}

/// The vectorised normals of 8 records (lane l <-> records[l]): normal n of lane l at
/// out[n·stride + l]. Runs the kernel of the SIMD level in use (vehs/sim/simd.hpp); every level
/// gives bitwise the numbers of CounterRng::normal_pair compiled without fused multiply-adds.
void fill_normals8(const CounterRng& rng, const std::uint32_t* records, Purpose purpose,
                   std::uint64_t first_pair, int pairs, double* out, std::size_t stride);

}  // namespace detail

/// Fills `out` with normals number [2·first_pair, 2·(first_pair + pairs)) of the `purpose`
/// stream of L records at once (lane l ↔ records[l]); out[n·L + l] is normal n of lane l.
/// The same numbers as CounterRng::normal (bitwise, where the compiler does not fuse the scalar
/// code's multiply-adds: a -march=native build may) — only vectorised. Each lane is computed
/// independently of the others, so a record's numbers do not depend on its batch.
template <int L>
void fill_normals(const CounterRng& rng, const std::array<std::uint32_t, L>& records,
                  Purpose purpose, std::uint64_t first_pair, int pairs, double* out) {
  if constexpr (L % 8 == 0) {
    for (int q = 0; q < L / 8; ++q)
      detail::fill_normals8(rng, records.data() + 8 * q, purpose, first_pair, pairs, out + 8 * q,
                            static_cast<std::size_t>(L));
  } else {
    detail::normal_pairs_portable(rng, records.data(), L, purpose, first_pair, pairs, out);
  }
}

}  // namespace vehs::sim
