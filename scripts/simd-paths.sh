#!/usr/bin/env bash
# Results must not depend on the SIMD width beyond rounding (issue 11). Two checks:
#
# 1. The run-time levels of the simulator's kernels (vehs/sim/simd.hpp): the portable build's
#    simulate-vehs run with VEHS_SIMD=scalar, sse2, avx2 and avx512 (those this CPU has) on the
#    same configs gives bitwise identical records and statistics (one source for the lane
#    arithmetic, -ffp-contract=off in every level: the design promises bitwise equality); and
#    identify-vehs at each level (its Gram kernel is dispatched the same way:
#    src/identify/simd/gram_kernel.inc) gives bitwise identical models on the same data.
#
# 2. Three builds of simulate-vehs and identify-vehs, each in its own folder under
#    $VEHS_SIMD_DIR (default ./build-simd):
#   scalar    no vector code the compiler chooses: EIGEN_DONT_VECTORIZE, -fno-tree-vectorize,
#             -fno-tree-slp-vectorize (the x86-64 baseline; the dispatched kernels as always)
#   portable  the default build (SSE2 outside the kernels); VEHS_SIMD_PORTABLE=<folder> reuses
#             an existing one
#   native    -march=native: the widest vector unit of this machine (AVX-512 here), with FMA
# runs them on the same configs (the paper's scheme; every effect of the catalogue through the
# general path; a continuous-time record set with Coulomb friction) and compares
# (scripts/simd_compare.py):
#   scalar vs portable: records and Monte Carlo statistics bitwise identical (lane-wise arithmetic
#     of IEEE doubles is the same at any width, and no sum changes order); identify-vehs models on
#     the same data within 1e-6 of a standard error (Eigen's reductions sum in another order).
#   portable vs native: the native build contracts a·b + c into fused multiply-adds outside the
#     kernels (GCC's default with FMA hardware: the general path's steps, initial conditions), so
#     records are not bitwise equal there (the fast path's kernels and the normals are: they are
#     compiled with -ffp-contract=off in every build). They start equal and separate at a rate set
#     by the dynamics: a multistable record hops between wells at other times once the rounding
#     has grown. The report says when. Statistics agree within 4.9·√2 standard errors (the bound
#     of simd_compare.py), identify-vehs models on the same data within 1e-6 SE.
# Usage: scripts/simd-paths.sh            (CI: .ci/run; about 3 builds of two executables)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
base="${VEHS_SIMD_DIR:-$root/build-simd}"
work="$base/run"
mkdir -p "$work"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

build() {  # name, extra cmake arguments...
  local dir="$base/$1"
  shift
  cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DVEHS_BUILD_TESTS=OFF \
    -DVEHS_BUILD_BENCH=OFF -DVEHS_WERROR="${VEHS_WERROR:-OFF}" "${launcher[@]}" "$@" >/dev/null
  cmake --build "$dir" -j "$(nproc)" --target simulate-vehs identify-vehs >"$dir.log" 2>&1 ||
    { tail -20 "$dir.log"; echo "simd-paths: build $dir failed" >&2; exit 1; }
}
echo "simd-paths: building scalar, portable and native simulate-vehs and identify-vehs in $base" >&2
build scalar "-DCMAKE_CXX_FLAGS=-DEIGEN_DONT_VECTORIZE -fno-tree-vectorize -fno-tree-slp-vectorize"
if [ -n "${VEHS_SIMD_PORTABLE:-}" ]; then
  portable="$VEHS_SIMD_PORTABLE"
  cmake --build "$portable" -j "$(nproc)" --target simulate-vehs identify-vehs >/dev/null
else
  build portable
  portable="$base/portable"
fi
build native -DVEHS_NATIVE=ON
flags="$(grep -o 'avx512[a-z]*\|avx2\|fma' /proc/cpuinfo 2>/dev/null | sort -u | tr '\n' ' ' || true)"
echo "simd-paths: this CPU: ${flags:-unknown}" >&2

cd "$work"
cat >paper.json <<'EOF'
{"model": {"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
           "diffusion": {"1": 0.02, "x^2": 0.01}},
 "trajectories": 16, "duration": 50, "dt": 0.001, "substeps": 1, "scheme": "rk4_euler", "seed": 27,
 "record_velocity": false, "output": "paper.npy", "statistics": {"output": "paper_stats.json"}}
EOF
cat >effects.json <<EOF
{"model": "$root/data/sim/effects_model.json",
 "trajectories": 16, "duration": 400, "dt": 0.01, "substeps": 10, "scheme": "taylor15", "seed": 5,
 "burn_in": 20, "record_velocity": false, "output": "effects.npy",
 "statistics": {"output": "effects_stats.json"}}
EOF
cat >friction.json <<'EOF'
{"model": {"drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1, "sign(y)": -0.05},
           "diffusion": {"1": 0.02, "x^2": 0.01}},
 "trajectories": 16, "duration": 200, "dt": 0.005, "substeps": 10, "scheme": "taylor15", "seed": 8,
 "record_velocity": false, "output": "friction.npy", "statistics": {"output": "friction_stats.json"}}
EOF

declare -A exe=([scalar]="$base/scalar" [portable]="$portable" [native]="$base/native")
for b in scalar portable native; do
  for c in paper effects friction; do
    "${exe[$b]}/simulate-vehs" -q "$c.json" --set "output=\"${c}_$b.npy\"" \
      --set "statistics={\"output\": \"${c}_stats_$b.json\"}"
  done
  # identify on the same data for every build: the scalar build's records
  echo "{\"data\": [\"paper_scalar.npy\"], \"output\": \"model_paper_$b.json\"}" >id_paper.json
  echo "{\"data\": [\"friction_scalar.npy\"], \"output\": \"model_friction_$b.json\",
         \"effects\": [{\"name\": \"coulomb_friction\"}]}" >id_friction.json
  "${exe[$b]}/identify-vehs" -q id_paper.json
  "${exe[$b]}/identify-vehs" -q id_friction.json
done

status=0
compare() { python3 "$root/scripts/simd_compare.py" "$@" || status=1; }

levels=(scalar sse2)
case " $flags " in *" avx2 "*) levels+=(avx2) ;; esac
case " $flags " in *" avx512f "*) case " $flags " in *" fma "*) levels+=(avx512) ;; esac ;; esac
for v in "${levels[@]}"; do
  for c in paper effects friction; do
    VEHS_SIMD="$v" "$portable/simulate-vehs" -q "$c.json" --set "output=\"${c}_level_$v.npy\"" \
      --set "statistics={\"output\": \"${c}_stats_level_$v.json\"}"
  done
done
for v in "${levels[@]}"; do
  for m in paper friction; do
    sed "s/model_${m}_[a-z]*\.json/model_${m}_level_$v.json/" "id_$m.json" >"id_${m}_level.json"
    VEHS_SIMD="$v" "$portable/identify-vehs" -q "id_${m}_level.json"
  done
done
for m in paper friction; do
  for v in "${levels[@]:1}"; do
    echo "== identify-vehs on the $m data: VEHS_SIMD=scalar vs VEHS_SIMD=$v (portable build)"
    compare model "model_${m}_level_scalar.json" "model_${m}_level_$v.json" --bitwise
  done
done
for c in paper effects friction; do
  for v in "${levels[@]:1}"; do
    echo "== $c: VEHS_SIMD=scalar vs VEHS_SIMD=$v (portable build)"
    compare records "${c}_level_scalar.npy" "${c}_level_$v.npy" --bitwise
    compare statistics "${c}_stats_level_scalar.json" "${c}_stats_level_$v.json" --bitwise
  done
done
for c in paper effects friction; do
  echo "== $c: scalar vs portable"
  compare records "${c}_scalar.npy" "${c}_portable.npy" --bitwise
  compare statistics "${c}_stats_scalar.json" "${c}_stats_portable.json" --bitwise
  echo "== $c: portable vs native"
  compare records "${c}_portable.npy" "${c}_native.npy"
  compare statistics "${c}_stats_portable.json" "${c}_stats_native.json"
done
for m in paper friction; do
  echo "== identify-vehs on the same $m data: scalar vs portable, portable vs native"
  compare model "model_${m}_scalar.json" "model_${m}_portable.json"
  compare model "model_${m}_portable.json" "model_${m}_native.json"
done
if [ "$status" -ne 0 ]; then echo "simd-paths: results depend on the SIMD width (see above)" >&2; fi
exit "$status"
