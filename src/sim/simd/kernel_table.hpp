#pragma once
// Internal: the entry points of the simulator's SIMD kernels, one table per instruction-set level
// (src/sim/simd/kernels.inc compiled per level; src/sim/simd_dispatch.cpp picks the table).
// Plain aggregates only: this header is included by code compiled for every level, so it defines
// no function.
#include <cstddef>
#include <cstdint>

#include "vehs/sim/detail/model_system.hpp"

namespace vehs::sim::detail {

/// One batch of 8 records of the fast path (PolynomialSystem): state, normals and stream
/// position. The kernels advance it; the engine stores and accumulates what they return.
struct FastBatch {
  static constexpr int kLanes = 8;
  static constexpr int kBlock = 64;  ///< steps of normals generated at once
  alignas(64) double normals[kBlock * 2 * kLanes];  ///< step n, normal k, lane l at (n·M + k)·8 + l
  double x[kLanes], y[kLanes];
  std::uint32_t records[kLanes];
  std::uint32_t key0 = 0, key1 = 0;
  std::uint64_t next_pair = 0;  ///< first Box–Muller pair of the next refill (Dynamics stream)
  int cursor = kBlock;          ///< steps used of `normals` (kBlock: empty)
};

/// What a fast-path kernel needs besides the batch.
struct FastRun {
  const CompiledModel::Fast* fast = nullptr;
  double h = 0.0;         ///< integration step
  int substeps = 1;       ///< steps per recorded interval
  double bound = 0.0;     ///< divergence bound on |x| and |y|
};

/// Advances `intervals` recorded intervals; after interval n writes x of the 8 lanes to
/// out[16n … 16n + 7] and y to out[16n + 8 … 16n + 15] (out may be null). Returns the number of
/// intervals completed before a lane left the bound (then the batch holds that state).
using FastAdvance = std::size_t (*)(const FastRun& run, FastBatch& batch, std::size_t intervals, double* out);
/// Normals [2·first_pair, 2·(first_pair + pairs)) of the stream (key, purpose) of 8 records:
/// normal n of lane l at out[n·stride + l].
using FillNormals8 = void (*)(std::uint32_t key0, std::uint32_t key1, const std::uint32_t* records,
                              std::uint32_t purpose, std::uint64_t first_pair, int pairs, double* out,
                              std::size_t stride);

struct SimdKernels {
  FillNormals8 fill_normals = nullptr;
  FastAdvance advance[4] = {};  ///< by Scheme
};

}  // namespace vehs::sim::detail

namespace vehs::sim::detail {
/// The table of the level in use (vehs/sim/simd.hpp: simd_level()).
const SimdKernels& simd_kernels();
}  // namespace vehs::sim::detail
