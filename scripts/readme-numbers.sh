#!/usr/bin/env bash
# The numbers of README and docs/ and the commands beside them (issue 15: "README's numbers reproduced by the
# commands next to them, or stated as machine-dependent").
#   scripts/readme-numbers.sh          list every figure of README's tables with its command and
#                                      class, then re-run the cheap ones and compare
#   scripts/readme-numbers.sh --list   only the list
# Classes: "re-run" (a test under a minute on an idle core, compared here within the tolerance
# the README row or its test states), "speed" (machine- and load-dependent benchmark figures,
# never compared), "study" (the hour-long benches and seed studies: not run here), "no command"
# (a table of figures without a reproduce column: the section's text says where they come from).
# Needs the test binaries (scripts/test.sh builds them); VEHS_BUILD_DIR as for scripts/build.sh.
# Exit status 1 when a re-run figure does not reproduce.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${VEHS_BUILD_DIR:-$root/build}"

python3 - "$root/README.md" "$root"/docs/*.md "$root"/docs/studies/*.md <<'EOF'
import os, re, sys
doc_tables = {"tool", "effect", "area (target)", "file", "option", "budget", "key"}  # documentation, not figures
cheap = ('test_sim "[convergence]"', "build/tests/test_fpk`", 'test_sim "[simd]"')
def cells(row):
    return [c.strip() for c in row.strip().strip("|").split("|")]
print("Figures of README and docs/ (file:line: what = measured [target] <- command; class)")
def scan(path, name):
  lines = open(path, encoding="utf-8").read().split("\n")
  i, last_cmd = 0, ""
  while i < len(lines):
      if lines[i].startswith("|") and i + 1 < len(lines) and re.match(r"^\|\s*-{3}", lines[i + 1]):
          head = [c.lower() for c in cells(lines[i])]
          i += 2
          if head[0] in doc_tables:
              while i < len(lines) and lines[i].startswith("|"): i += 1
              continue
          rc = head.index("reproduce") if "reproduce" in head else -1
          tc = head.index("target") if "target" in head else -1
          while i < len(lines) and lines[i].startswith("|"):
              c = cells(lines[i])
              what, measured = c[0], " / ".join(c[1:rc if rc > 0 else (tc if tc > 0 else len(c))])
              target = c[tc] if tc >= 0 and tc < len(c) else ""
              cmd = c[rc] if 0 <= rc < len(c) else ""
              if cmd.startswith("same"): cmd = last_cmd + cmd[4:]
              if cmd: last_cmd = cmd.split(" (")[0]
              if not cmd: cls = "no command"
              elif any(k in cmd for k in cheap): cls = "re-run"
              elif re.search(r"M/s|\d s\b|×|wall|CPU time|per core|\bcores\b", what + " " + measured): cls = "speed"
              else: cls = "study"
              short = lambda s, n: s if len(s) <= n else s[: n - 3] + "..."
              print(f"  {name}:{i + 1}: {short(what, 70)} = {short(measured, 60)}" + (f" [{short(target, 20)}]" if target else "")
                    + f" <- {short(cmd, 70) or '-'}; {cls}")
              i += 1
          continue
      i += 1
for path in sys.argv[1:]:
  if os.path.exists(path):
    scan(path, os.path.relpath(path, os.path.dirname(os.path.abspath(sys.argv[1]))))
EOF
[ "${1:-}" = "--list" ] && exit 0

status=0
compare() {  # name README-value measured tolerance(absolute)
  if awk -v a="$2" -v b="$3" -v t="$4" 'BEGIN { exit !((a - b) <= t && (b - a) <= t) }'; then
    echo "  reproduces: $1: README $2, measured $3 (tolerance ±$4)"
  else
    echo "  DOES NOT REPRODUCE: $1: README $2, measured $3 (tolerance ±$4)"
    status=1
  fi
}
need() { [ -x "$build/tests/$1" ] || { echo "  $build/tests/$1 missing: run scripts/test.sh first"; exit 2; }; }
echo "Re-running the cheap figures ($build, load average $(cut -d' ' -f1-3 /proc/loadavg)):"
log=$(mktemp)
trap 'rm -f "$log"' EXIT

# FPK L1 error vs the exact Q = 0 density at 400² and the observed order (deterministic: the
# direct solve; README 1.31e-4, order 2.07, printed to 3 significant digits)
need test_fpk
"$build/tests/test_fpk" "Q = 0: flux scheme reaches L1 <= 2e-4 on 400x400 and converges with order 2" -s >"$log" 2>&1 || true
line=$(grep -m1 "Q=0 flux L1:" "$log" || echo "Q=0 flux L1: nan nan nan, observed orders nan nan")
compare "FPK L1 error, 400²" 1.31e-4 "$(echo "$line" | awk '{print $6}' | tr -d ,)" 0.006e-4
compare "FPK observed order" 2.07 "$(echo "$line" | awk '{print $NF}')" 0.006

# strong orders (README: EM 1.01, Eq. 30 1.01, BAOAB 1.00, Taylor 1.5 1.65): the test's model with
# multiplicative noise in x ("sigma(x)"), fixed seeds, so README's two decimals reproduce exactly
need test_sim
"$build/tests/test_sim" "[convergence]" -s >"$log" 2>&1 || true
for pair in "euler_maruyama 1.01" "rk4_euler 1.01" "baoab 1.00" "taylor15 1.65"; do
  set -- $pair
  compare "strong order $1, sigma(x)" "$2" \
    "$(awk -v s="$1" '$1 == "strong" && $3 == s && $4 == "sigma(x)" && $5 ~ /^[0-9.]+$/ { print $5; exit }' "$log")" 0.006
done

# SIMD levels bitwise (README: records and statistics bitwise identical at every level)
if "$build/tests/test_sim" "[simd]" >"$log" 2>&1; then
  echo "  reproduces: SIMD levels bitwise identical ($(grep -m1 -o 'All tests passed.*' "$log"))"
else
  echo "  DOES NOT REPRODUCE: SIMD levels bitwise identical: $(grep -m1 -E 'FAILED|failed' "$log")"
  status=1
fi
exit $status
