#pragma once
// The instruction-set level of the simulator's vector kernels (normals, the fast path's drift and
// steppers), chosen at run time: the library carries one compiled copy of the kernels per level
// (from one source, src/sim/simd/) and uses the widest one this CPU has, or the one named by the
// environment variable VEHS_SIMD (scalar, sse2, avx2, avx512) or by set_simd_level. Every level
// does the same IEEE operations in the same order (no fused multiply-add), so results are
// bitwise identical whatever the level: the level changes the speed only
// (tests/sim/test_simd.cpp, scripts/simd-paths.sh).
namespace vehs::sim {

enum class SimdLevel {
  Scalar,  ///< one double at a time (the x86-64 baseline without vector code)
  Sse2,    ///< 2 doubles per register (every x86-64 CPU)
  Avx2,    ///< 4 doubles per register
  Avx512,  ///< 8 doubles per register (AVX-512F)
};

/// "scalar", "sse2", "avx2" or "avx512".
const char* simd_level_name(SimdLevel level);
/// Whether this CPU (and its operating system) can run the level.
bool simd_level_supported(SimdLevel level);
/// The widest level this CPU can run.
SimdLevel best_simd_level();
/// The level in use: set_simd_level's, else VEHS_SIMD's (read once; throws vehs::Error naming
/// the variable if its value is not a level or the CPU cannot run it), else the best.
SimdLevel simd_level();
/// Uses `level` from now on (for every thread); throws vehs::Error if the CPU cannot run it.
void set_simd_level(SimdLevel level);

}  // namespace vehs::sim
