#!/usr/bin/env bash
# ODR safety of the per-level SIMD kernels (src/sim/simd/simd.cmake: the simulator's and
# identify's Gram kernel): every symbol that the objects of a level define with external linkage
# (functions, weak template or inline instances, data) lies in that level's namespace
# vehs::<area>::simd_<level>. An inline function of Eigen or the
# standard library compiled with -mavx512f and emitted as a weak symbol would otherwise be free
# for the linker to pick for every caller, baseline code included, and crash CPUs without it.
# Usage: simd_symbols.sh BUILD_DIR LEVEL...   (CTest: tests/CMakeLists.txt)
set -euo pipefail
build="$1"
shift
status=0
for area in sim identify; do
for level in "$@"; do
  objs=$(find "$build/CMakeFiles/vehs_${area}_simd_$level.dir" -name '*.o' | sort)
  if [ -z "$objs" ]; then echo "simd_symbols: no objects for $area level $level under $build" >&2; exit 1; fi
  # defined symbols that are not local (upper-case nm types, plus u/v/w for unique/weak objects)
  bad=$(nm -C --defined-only $objs | awk -v ns="vehs::${area}::simd_${level}::" '
    NF >= 3 && $2 ~ /^[A-Zuvw]$/ {
      name = $0; sub(/^[^ ]* [^ ]* /, "", name)
      sub(/^(void|unsigned long|double|bool|int) /, "", name)
      if (index(name, ns) != 1) print name
    }' | sort -u)
  n=$(echo "$objs" | wc -l)
  if [ -n "$bad" ]; then
    echo "simd_symbols: $level: symbols outside vehs::${area}::simd_$level:"
    echo "$bad" | head -20
    status=1
  else
    echo "simd_symbols: $level: $n objects, every external symbol in vehs::${area}::simd_$level"
  fi
done
done
exit "$status"
