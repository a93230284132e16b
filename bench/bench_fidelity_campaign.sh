#!/usr/bin/env bash
# Issue #16's fidelity benchmark: collect (or resume) the fidelity campaign, then print its
# comparison with the seed study (the five bars with 95 % bootstrap intervals, the per-building
# table) and draw the ratio-against-area plot.
#
#   bench/bench_fidelity_campaign.sh [--collect] [--jobs K] [--campaign NAME] [--plot PNG]
#
# Without --collect it only measures the committed run.json files (seconds: what CI could run);
# with it, tools/run_campaign.sh NAME first adds whatever runs are missing (hours: the 51 runs
# of fidelity_seed_study take about 8 h of one core; the wall time of each is in its run.json).
# NAME: fidelity_seed_study (default; config/fidelity/seed_study.yaml) or any campaign of
# tools/run_campaign.sh. Needs ../shared/data (or SLAM_PREDICT_DATA) for the seed study's table.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
NAME=fidelity_seed_study; JOBS=2; COLLECT=0; PLOT=""
while [ $# -gt 0 ]; do
  case "$1" in
    --collect) COLLECT=1; shift ;;
    --jobs) JOBS="$2"; shift 2 ;;
    --campaign) NAME="$2"; shift 2 ;;
    --plot) PLOT="$2"; shift 2 ;;
    *) echo "bench_fidelity_campaign: unknown argument $1" >&2; exit 2 ;;
  esac
done
DATA_DIR="${SLAM_PREDICT_DATA:-$ROOT/../shared/data}"
THESIS="$DATA_DIR/thesis/stats_realistic.csv"
[ -f "$THESIS" ] || { echo "bench_fidelity_campaign: $THESIS not found (set SLAM_PREDICT_DATA)" >&2; exit 2; }
[ -f "$ROOT/setup.bash" ] || bash "$ROOT/tools/setup.sh"
set +u; source "$ROOT/setup.bash"; set -u
if [ "$COLLECT" = 1 ]; then
  start=$(date +%s)
  "$ROOT/tools/run_campaign.sh" "$NAME" --jobs "$JOBS"
  echo "collection: $(( $(date +%s) - start )) s wall with --jobs $JOBS"
fi
PLOT_ARGS=()
[ -n "$PLOT" ] && PLOT_ARGS=(--plot "$PLOT")
slam-predict fidelity "$ROOT/data/campaigns/$NAME" --thesis "$THESIS" --min-coverage 0.5 \
  "${PLOT_ARGS[@]}"
