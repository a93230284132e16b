#!/usr/bin/env bash
# `make demo`: the main job on shipped worlds, end to end. Outputs go under $1 (default out/demo):
#   worlds/   preview of a shipped world
#   data/     a small collection campaign (GMapping in the loop), its run records and summary.csv
#   features/ the feature vector and overlay of a shipped world
#   predict.json / predict.txt  the predicted GMapping error of that world
#   report.html  one self-contained page: campaign overview, error tables, maps, predictions
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-$ROOT/out/demo}"
set +u; source "$ROOT/setup.bash"; set -u
mkdir -p "$OUT/worlds" "$OUT/features"
WORLD="$ROOT/worlds/office_500.world"

echo "[demo] 1/4 validate and render $WORLD"
slam-predict worlds validate "$WORLD"
slam-predict worlds show "$WORLD" --out "$OUT/worlds/office_500.png" --force

echo "[demo] 2/4 collect: simulated explorations with GMapping (tiny + office_150, resumable)"
slam-predict collect "$ROOT/worlds/tiny.world" "$ROOT/worlds/office_150.world" \
  --runs "${DEMO_RUNS:-1}" --jobs 2 --out "$OUT/data" --no-progress
cat "$OUT/data/summary.csv"

echo "[demo] 3/4 features of office_500"
slam-predict features "$WORLD" --json --force --overlay "$OUT/features/office_500_overlay.png" \
  > "$OUT/features/office_500.json"

echo "[demo] 4/4 predict GMapping's error in office_500 (shipped model)"
slam-predict predict "$WORLD" | tee "$OUT/predict.txt"
slam-predict predict "$WORLD" --json > "$OUT/predict.json"

echo "[demo] report of the demo campaign, with the shipped models' predictions for its worlds"
slam-predict report "$OUT/data" --models-dir "$ROOT/models" --out "$OUT/report.html" --force \
  --title "slam_predict demo campaign"
echo "[demo] done: outputs in $OUT"
