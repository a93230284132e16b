#!/usr/bin/env bash
# `make bench`: the benchmarks that need no argument, no upstream checkout and no campaign run,
# each with its defaults (minutes each on 2 cores); prints one summary line. The others take a
# building, a campaign folder or an upstream checkout, or run for hours: their commands are in
# docs/benchmarks.md, each table with the command that measured it.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
set +u; source "$ROOT/setup.bash"; set -u
PY="$ROOT/.venv/bin/python"
QUICK=(bench_metric bench_worlds bench_sim bench_generator bench_features bench_plan_memory
       bench_ros_path bench_seed_study_noise_floor)
passed=0; failed=0
for name in "${QUICK[@]}"; do
  echo "== bench/$name.py"
  if "$PY" "bench/$name.py"; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done
echo "make bench: $passed of ${#QUICK[@]} benchmarks ran ($failed failed); the others' commands" \
     "are in docs/benchmarks.md"
[ "$failed" -eq 0 ]
