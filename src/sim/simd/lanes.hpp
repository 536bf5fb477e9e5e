#pragma once
// The lane type of the simulator's SIMD kernels: 8 doubles (8 records) advanced in lockstep, with
// the subset of Eigen's array interface the systems and steppers use (arithmetic with lanes and
// scalars, sqrt, abs, comparisons and select, Constant/Zero, col() of a state).
//
// One source for every instruction set. This header is compiled once per level by the
// translation units generated in src/sim/simd/simd.cmake, each with VEHS_SIMD_ISA naming the
// level (scalar, sse2, avx2, avx512) and its own -m flags; everything here lives in the
// namespace vehs::sim::simd_<level>, so no inline function compiled for one level can be picked
// by the linker for another (ODR-safe; tests/sim/simd_symbols.sh checks the objects).
// 8 lanes are held as pieces of the level's native width (GCC/Clang vector extensions): 8 × 1
// double (scalar, compiled without auto-vectorisation), 4 × 2 (SSE2), 2 × 4 (AVX2), 1 × 8
// (AVX-512); every operation is a loop over the pieces (unrolled), so each piece stays in a
// register. sqrt, Philox's 32×32→64-bit multiplication and the all-lanes test use the level's
// intrinsics. Every operation is lane-wise IEEE arithmetic, and the kernels are compiled with
// -ffp-contract=off (no fused multiply-add anywhere), so every level gives bitwise the same
// numbers.
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

#if !defined(VEHS_SIMD_ISA)
#error "lanes.hpp is compiled through the generated per-level units (src/sim/simd/simd.cmake)"
#endif
#if !VEHS_SIMD_SCALAR
#include <immintrin.h>
#endif

#define VEHS_SIMD_CAT_(a, b) a##b
#define VEHS_SIMD_CAT(a, b) VEHS_SIMD_CAT_(a, b)
#define VEHS_SIMD_NS VEHS_SIMD_CAT(simd_, VEHS_SIMD_ISA)
#define VEHS_LANE_INLINE inline __attribute__((always_inline))

namespace vehs::sim::VEHS_SIMD_NS {

inline constexpr int kL = 8;

// ---- pieces: the level's native register of doubles (PD) and of 64-bit integers (PU, PI) ------
#if VEHS_SIMD_SCALAR
inline constexpr int kWidth = 1;
using PD = double;
using PU = std::uint64_t;
using PI = std::int64_t;
#else
#if defined(__AVX512F__)
inline constexpr int kWidth = 8;
#elif defined(__AVX2__)
inline constexpr int kWidth = 4;
#else
inline constexpr int kWidth = 2;
#endif
using PD = double __attribute__((vector_size(8 * kWidth)));
using PU = std::uint64_t __attribute__((vector_size(8 * kWidth)));
using PI = std::int64_t __attribute__((vector_size(8 * kWidth)));
#endif
inline constexpr int kPieces = kL / kWidth;
inline constexpr bool kScalar = kWidth == 1;

template <class P, class T, std::size_t... I>
VEHS_LANE_INLINE P broadcast_list(T v, std::index_sequence<I...>) {
  return P{(static_cast<void>(I), v)...};  // {v, v, …}: one broadcast instruction
}
template <class P, class T>
VEHS_LANE_INLINE P broadcast(T v) {
  if constexpr (kScalar)
    return v;
  else
    return broadcast_list<P>(v, std::make_index_sequence<kWidth>{});
}
template <class To, class From>
VEHS_LANE_INLINE To bit_cast_piece(const From& a) {
  static_assert(sizeof(To) == sizeof(From));
  To r;
  std::memcpy(&r, &a, sizeof r);
  return r;
}
/// a < b etc. as a mask piece (all bits set where true).
#if VEHS_SIMD_SCALAR
#define VEHS_PIECE_COMPARE(name, op) \
  VEHS_LANE_INLINE PI name(PD a, PD b) { return (a op b) ? PI(-1) : PI(0); }
#else
#define VEHS_PIECE_COMPARE(name, op) \
  VEHS_LANE_INLINE PI name(PD a, PD b) { return a op b; }
#endif
VEHS_PIECE_COMPARE(piece_lt, <)
VEHS_PIECE_COMPARE(piece_gt, >)
VEHS_PIECE_COMPARE(piece_le, <=)
#undef VEHS_PIECE_COMPARE

VEHS_LANE_INLINE PD piece_sqrt(PD a) {
#if VEHS_SIMD_SCALAR
  return __builtin_sqrt(a);
#elif defined(__AVX512F__)
  // the masked form: GCC 12's unmasked one starts from _mm512_undefined_pd, which trips
  // -Wuninitialized once inlined
  return _mm512_mask_sqrt_pd(a, 0xFF, a);
#elif defined(__AVX2__)
  return _mm256_sqrt_pd(a);
#else
  return _mm_sqrt_pd(a);
#endif
}
/// (a mod 2³²)·(b mod 2³²) (pmuludq).
VEHS_LANE_INLINE PU piece_mul_lo32(PU a, PU b) {
#if VEHS_SIMD_SCALAR
  return (a & 0xFFFFFFFFu) * (b & 0xFFFFFFFFu);
#elif defined(__AVX512F__)
  const __m512i p = reinterpret_cast<__m512i>(a), q = reinterpret_cast<__m512i>(b);
  return reinterpret_cast<PU>(_mm512_mask_mul_epu32(p, 0xFF, p, q));
#elif defined(__AVX2__)
  return reinterpret_cast<PU>(_mm256_mul_epu32(reinterpret_cast<__m256i>(a), reinterpret_cast<__m256i>(b)));
#else
  return reinterpret_cast<PU>(_mm_mul_epu32(reinterpret_cast<__m128i>(a), reinterpret_cast<__m128i>(b)));
#endif
}
VEHS_LANE_INLINE bool piece_all(PI m) {
#if VEHS_SIMD_SCALAR
  return m != 0;
#elif defined(__AVX512F__)
  const __m512i p = reinterpret_cast<__m512i>(m);
  return _mm512_test_epi64_mask(p, p) == 0xFF;
#elif defined(__AVX2__)
  return _mm256_movemask_pd(reinterpret_cast<__m256d>(m)) == 0xF;
#else
  return _mm_movemask_pd(reinterpret_cast<__m128d>(m)) == 0x3;
#endif
}

// ---- 8 lanes as kPieces pieces ------------------------------------------------------------
template <class P>
struct Arr {
  P p[kPieces];
};
using F64 = Arr<PD>;
using U64 = Arr<PU>;
using I64 = Arr<PI>;

#define VEHS_ARR_BINARY(op)                                                                     \
  template <class P>                                                                            \
  VEHS_LANE_INLINE Arr<P> operator op(const Arr<P>& a, const Arr<P>& b) {                       \
    Arr<P> r;                                                                                   \
    for (int i = 0; i < kPieces; ++i) r.p[i] = a.p[i] op b.p[i];                                \
    return r;                                                                                   \
  }
VEHS_ARR_BINARY(+)
VEHS_ARR_BINARY(-)
VEHS_ARR_BINARY(*)
VEHS_ARR_BINARY(/)
VEHS_ARR_BINARY(&)
VEHS_ARR_BINARY(|)
VEHS_ARR_BINARY(^)
#undef VEHS_ARR_BINARY
template <class P>
VEHS_LANE_INLINE Arr<P> operator-(const Arr<P>& a) {
  Arr<P> r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = -a.p[i];
  return r;
}
VEHS_LANE_INLINE U64 operator<<(const U64& a, int n) {
  U64 r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = a.p[i] << n;
  return r;
}
VEHS_LANE_INLINE U64 operator>>(const U64& a, int n) {
  U64 r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = a.p[i] >> n;
  return r;
}
#define VEHS_ARR_COMPARE(op, piece)                                                             \
  VEHS_LANE_INLINE I64 operator op(const F64& a, const F64& b) {                                \
    I64 r;                                                                                      \
    for (int i = 0; i < kPieces; ++i) r.p[i] = piece(a.p[i], b.p[i]);                           \
    return r;                                                                                   \
  }
VEHS_ARR_COMPARE(<, piece_lt)
VEHS_ARR_COMPARE(>, piece_gt)
VEHS_ARR_COMPARE(<=, piece_le)
#undef VEHS_ARR_COMPARE

VEHS_LANE_INLINE F64 splat(double v) {
  F64 r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = broadcast<PD>(v);
  return r;
}
VEHS_LANE_INLINE U64 splat(std::uint64_t v) {
  U64 r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = broadcast<PU>(v);
  return r;
}
// a lane-wise operation with a scalar broadcasts it first (the pieces then see the same values)
#define VEHS_ARR_SCALAR(op)                                                                     \
  VEHS_LANE_INLINE F64 operator op(const F64& a, double b) { return a op splat(b); }           \
  VEHS_LANE_INLINE F64 operator op(double a, const F64& b) { return splat(a) op b; }
VEHS_ARR_SCALAR(+)
VEHS_ARR_SCALAR(-)
VEHS_ARR_SCALAR(*)
VEHS_ARR_SCALAR(/)
#undef VEHS_ARR_SCALAR

/// Lane-wise a where m is set, b elsewhere.
template <class P>
VEHS_LANE_INLINE Arr<P> blend(const I64& m, const Arr<P>& a, const Arr<P>& b) {
  Arr<P> r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = m.p[i] ? a.p[i] : b.p[i];
  return r;
}
VEHS_LANE_INLINE U64 bits_of(const F64& a) { return bit_cast_piece<U64>(a); }
VEHS_LANE_INLINE F64 double_of(const U64& a) { return bit_cast_piece<F64>(a); }
VEHS_LANE_INLINE F64 sqrt_lanes(const F64& a) {
  F64 r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = piece_sqrt(a.p[i]);
  return r;
}
/// (a mod 2³²)·(b mod 2³²) as 64-bit lanes.
VEHS_LANE_INLINE U64 mul_lo32(const U64& a, const U64& b) {
  U64 r;
  for (int i = 0; i < kPieces; ++i) r.p[i] = piece_mul_lo32(a.p[i], b.p[i]);
  return r;
}
VEHS_LANE_INLINE bool all_set(const I64& m) {
  bool ok = true;
  for (int i = 0; i < kPieces; ++i) ok = ok && piece_all(m.p[i]);
  return ok;
}

/// All bits set in the lanes of `a` whose bit number `bit` is set.
VEHS_LANE_INLINE I64 bit_set(const U64& a, int bit) {
  const U64 m = splat(std::uint64_t{0}) - ((a >> bit) & splat(std::uint64_t{1}));
  I64 r;
  std::memcpy(&r, &m, sizeof r);
  return r;
}

/// Lanes of doubles with the part of Eigen's Array interface the systems and steppers use.
struct Lanes {
  F64 v;

  static VEHS_LANE_INLINE Lanes Constant(double c) { return {splat(c)}; }
  static VEHS_LANE_INLINE Lanes Zero() { return {splat(0.0)}; }
  static VEHS_LANE_INLINE Lanes load(const double* p) {
    Lanes r;
    std::memcpy(&r.v, p, sizeof r.v);
    return r;
  }
  VEHS_LANE_INLINE void store(double* p) const { std::memcpy(p, &v, sizeof v); }

  VEHS_LANE_INLINE Lanes sqrt() const { return {sqrt_lanes(v)}; }
  VEHS_LANE_INLINE Lanes abs() const { return {double_of(bits_of(v) & splat(std::uint64_t{0x7FFFFFFFFFFFFFFFull}))}; }
  VEHS_LANE_INLINE Lanes operator-() const { return {-v}; }
  VEHS_LANE_INLINE Lanes& operator+=(const Lanes& o) { v = v + o.v; return *this; }
  VEHS_LANE_INLINE Lanes& operator-=(const Lanes& o) { v = v - o.v; return *this; }
  VEHS_LANE_INLINE Lanes& operator*=(const Lanes& o) { v = v * o.v; return *this; }
};

#define VEHS_LANES_BINARY(op)                                                                                  \
  VEHS_LANE_INLINE Lanes operator op(const Lanes& a, const Lanes& b) { return {a.v op b.v}; }                 \
  VEHS_LANE_INLINE Lanes operator op(const Lanes& a, double b) { return {a.v op b}; }                          \
  VEHS_LANE_INLINE Lanes operator op(double a, const Lanes& b) { return {a op b.v}; }
VEHS_LANES_BINARY(+)
VEHS_LANES_BINARY(-)
VEHS_LANES_BINARY(*)
VEHS_LANES_BINARY(/)
#undef VEHS_LANES_BINARY

/// The result of a lane-wise comparison (all bits set where true).
struct Mask {
  I64 m;
  /// Lane-wise a where true, b elsewhere (Eigen's select).
  VEHS_LANE_INLINE Lanes select(const Lanes& a, const Lanes& b) const { return {blend(m, a.v, b.v)}; }
  VEHS_LANE_INLINE Lanes select(const Lanes& a, double b) const { return {blend(m, a.v, splat(b))}; }
  VEHS_LANE_INLINE bool all() const { return all_set(m); }
};
#define VEHS_LANES_COMPARE(op)                                                                                 \
  VEHS_LANE_INLINE Mask operator op(const Lanes& a, const Lanes& b) { return {a.v op b.v}; }                  \
  VEHS_LANE_INLINE Mask operator op(const Lanes& a, double b) { return {a.v op splat(b)}; }
VEHS_LANES_COMPARE(<)
VEHS_LANES_COMPARE(>)
VEHS_LANES_COMPARE(<=)
#undef VEHS_LANES_COMPARE

/// D components of 8 trajectories (Eigen's L×D array: component c is col(c)).
template <int D>
struct Cols {
  Lanes c[D];
  VEHS_LANE_INLINE Lanes& col(int i) { return c[i]; }
  VEHS_LANE_INLINE const Lanes& col(int i) const { return c[i]; }
  VEHS_LANE_INLINE Cols& operator+=(const Cols& o) {
    for (int i = 0; i < D; ++i) c[i] += o.c[i];
    return *this;
  }
  friend VEHS_LANE_INLINE Cols operator+(Cols a, const Cols& b) { return a += b; }
  friend VEHS_LANE_INLINE Cols operator*(double a, const Cols& b) {
    Cols r;
    for (int i = 0; i < D; ++i) r.c[i] = a * b.c[i];
    return r;
  }
};

/// The normals of one step: normal k of lane l at p[k·8 + l].
struct Normals {
  const double* p;
};

/// The steppers' component<System>(s, c) for these types (found by argument-dependent lookup).
template <class System, int D>
VEHS_LANE_INLINE Lanes& component(Cols<D>& s, int c) {
  return s.c[c];
}
template <class System, int D>
VEHS_LANE_INLINE const Lanes& component(const Cols<D>& s, int c) {
  return s.c[c];
}
template <class System>
VEHS_LANE_INLINE Lanes component(const Normals& xi, int k) {
  return Lanes::load(xi.p + k * kL);
}

/// The lane types a system is built on (see PolynomialSystem).
struct LaneTypes {
  using Lanes = VEHS_SIMD_NS::Lanes;
  using State = Cols<2>;
  using Noise = Cols<1>;
};

}  // namespace vehs::sim::VEHS_SIMD_NS
