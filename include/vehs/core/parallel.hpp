#pragma once
// Threads of the library's parallel loops (OpenMP). By default OpenMP's own choice (all cores, or
// OMP_NUM_THREADS); set_threads changes it for the whole process. Results never depend on it:
// every parallel reduction of the library runs in a fixed order.
namespace vehs {

/// Threads used by subsequent parallel loops; 0 restores the default.
void set_threads(int threads);
/// Threads a parallel loop started now would use (1 without OpenMP).
int max_threads();

}  // namespace vehs
