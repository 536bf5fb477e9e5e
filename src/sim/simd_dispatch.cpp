// Run-time choice of the simulator's kernel level (vehs/sim/simd.hpp) and the entry points that
// the rest of the library calls through it.
#include <atomic>
#include <cstdlib>
#include <string>

#include "simd/kernel_table.hpp"
#include "vehs/core/error.hpp"
#include "vehs/sim/random.hpp"
#include "vehs/sim/simd.hpp"

namespace vehs::sim {

// the per-level tables (src/sim/simd/kernels.inc, compiled once per level)
namespace simd_scalar { const detail::SimdKernels& kernels(); }
namespace simd_sse2 { const detail::SimdKernels& kernels(); }
namespace simd_avx2 { const detail::SimdKernels& kernels(); }
namespace simd_avx512 { const detail::SimdKernels& kernels(); }

namespace {

constexpr SimdLevel kLevels[] = {SimdLevel::Scalar, SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512};

SimdLevel from_environment() {
  const char* v = std::getenv("VEHS_SIMD");
  if (!v || !*v) return best_simd_level();
  for (SimdLevel l : kLevels)
    if (std::string(v) == simd_level_name(l)) {
      if (!simd_level_supported(l))
        throw Error(std::string("VEHS_SIMD=") + v + ": this CPU cannot run the " + v + " kernels (best: " +
                    simd_level_name(best_simd_level()) + ")");
      return l;
    }
  throw Error(std::string("VEHS_SIMD=") + v + ": expected scalar, sse2, avx2 or avx512");
}

constexpr int kUnset = -1;
std::atomic<int> g_level{kUnset};

}  // namespace

const char* simd_level_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::Scalar: return "scalar";
    case SimdLevel::Sse2: return "sse2";
    case SimdLevel::Avx2: return "avx2";
    case SimdLevel::Avx512: return "avx512";
  }
  return "?";
}

bool simd_level_supported(SimdLevel level) {
  switch (level) {
    case SimdLevel::Scalar:
    case SimdLevel::Sse2: return true;
    case SimdLevel::Avx2: return __builtin_cpu_supports("avx2");
    case SimdLevel::Avx512: return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma");
  }
  return false;
}

SimdLevel best_simd_level() {
  static const SimdLevel best = [] {
    SimdLevel b = SimdLevel::Sse2;
    for (SimdLevel l : kLevels)
      if (simd_level_supported(l)) b = l;
    return b;
  }();
  return best;
}

SimdLevel simd_level() {
  int l = g_level.load(std::memory_order_relaxed);
  if (l == kUnset) {
    l = static_cast<int>(from_environment());
    int expected = kUnset;
    if (!g_level.compare_exchange_strong(expected, l)) l = expected;
  }
  return static_cast<SimdLevel>(l);
}

void set_simd_level(SimdLevel level) {
  if (!simd_level_supported(level))
    throw Error(std::string("SIMD level ") + simd_level_name(level) + ": this CPU cannot run it (best: " +
                simd_level_name(best_simd_level()) + ")");
  g_level.store(static_cast<int>(level));
}

namespace detail {

const SimdKernels& simd_kernels() {
  switch (simd_level()) {
    case SimdLevel::Scalar: return simd_scalar::kernels();
    case SimdLevel::Sse2: return simd_sse2::kernels();
    case SimdLevel::Avx2: return simd_avx2::kernels();
    case SimdLevel::Avx512: return simd_avx512::kernels();
  }
  return simd_sse2::kernels();
}

void fill_normals8(const CounterRng& rng, const std::uint32_t* records, Purpose purpose, std::uint64_t first_pair,
                   int pairs, double* out, std::size_t stride) {
  simd_kernels().fill_normals(rng.key0(), rng.key1(), records, static_cast<std::uint32_t>(purpose), first_pair,
                              pairs, out, stride);
}

}  // namespace detail
}  // namespace vehs::sim
