#pragma once
// Internal: the machine's physical memory, for the memory limits of allocations that scale with
// an option (simulated records, FPK grids).
#include <unistd.h>

namespace vehs::detail {

/// Bytes of physical memory (8e9 when the system does not say).
inline double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 8e9;
}

/// The limit used when an option's own is 0: three quarters of physical memory.
inline double default_memory_limit(double option) { return option > 0.0 ? option : 0.75 * physical_memory_bytes(); }

}  // namespace vehs::detail
