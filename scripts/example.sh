#!/usr/bin/env bash
# The main job on the built-in example, the paper's penta-stable harvester (Eq. 27):
# install what is missing, build, then
#   simulate-vehs   100 records x 10^5 samples, dt = 0.001, the paper's scheme (Eq. 30)
#   identify-vehs   learn drift and diffusion with standard errors (default settings)
#   fpk-stationary  stationary density of the LEARNED model: E[X^2], E[Y^2]
#   simulate-vehs   Monte Carlo of the learned model, for an independent E[X^2], E[Y^2]
#   vehs-compare    table of true / paper-reported / learned parameters
# Outputs go to out/paper/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" simulate-vehs identify-vehs fpk-stationary vehs-compare
cd "$root"
bin="$root/build"
mkdir -p out/paper
step() { printf '\n== %s\n' "$*" >&2; }
step "simulate the paper's penta-stable harvester (data/paper/simulate.json)"
"$bin/simulate-vehs" data/paper/simulate.json
step "identify drift and diffusion from x(t) only (data/paper/identify.json)"
"$bin/identify-vehs" data/paper/identify.json
step "stationary Fokker-Planck equation of the learned model (data/paper/fpk.json)"
"$bin/fpk-stationary" data/paper/fpk.json
step "Monte Carlo of the learned model (data/paper/monte_carlo.json)"
"$bin/simulate-vehs" data/paper/monte_carlo.json
step "learned vs true"
"$bin/vehs-compare" data/paper/compare.json
