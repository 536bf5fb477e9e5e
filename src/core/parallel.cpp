#include "vehs/core/parallel.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace vehs {

void set_threads(int threads) {
#ifdef _OPENMP
  static const int default_threads = omp_get_max_threads();
  omp_set_num_threads(threads > 0 ? threads : default_threads);
#else
  (void)threads;
#endif
}

int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

}  // namespace vehs
