#pragma once
// Inline every call inside the filter's hot functions: with ceres::Jet scalars the compiler
// otherwise leaves each Jet operation (a small Eigen vector loop) as an out-of-line call, which
// was half of the likelihood's CPU time (bench/likelihood.sh speed).
#if defined(__GNUC__)
#define VEHS_FLATTEN __attribute__((flatten))
#else
#define VEHS_FLATTEN
#endif
