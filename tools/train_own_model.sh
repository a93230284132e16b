#!/usr/bin/env bash
# Train models/own-realistic from one of the project's own campaigns, by default the fidelity
# campaign of the chain of record, data/campaigns/fidelity_seed_study_6 (tools/run_campaign.sh
# fidelity_seed_study_6; issue #41): its summary.csv joined with our features of the
# campaign's worlds (the seed-study buildings rebuilt by `worlds import-thesis`, the shipped
# ones from worlds/).
# Usage: tools/train_own_model.sh [OUT]   (intermediate files in OUT, default out/own_model)
# Environment: CAMPAIGN (default data/campaigns/fidelity_seed_study_6; the model came from
# data/campaigns/realistic with MIN_RUNS=5 until 2026-12-04, from fidelity_seed_study until
# 2026-12-07), SLAM_PREDICT_DATA (default ../shared/data), MIN_RUNS (default 3), JOBS (default
# 2), MODELS (default models/).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-$ROOT/out/own_model}"
mkdir -p "$OUT"; OUT="$(cd "$OUT" && pwd)"   # absolute: the world links below must resolve
CAMPAIGN="${CAMPAIGN:-$ROOT/data/campaigns/fidelity_seed_study_6}"
DATA_DIR="${SLAM_PREDICT_DATA:-$ROOT/../shared/data}"
MIN_RUNS="${MIN_RUNS:-3}"
JOBS="${JOBS:-2}"
MODELS="${MODELS:-$ROOT/models}"
set +u; source "$ROOT/setup.bash"; set -u
rm -rf "$OUT/worlds"; mkdir -p "$OUT/worlds"
[ -f "$CAMPAIGN/summary.csv" ] || { echo "train_own_model: $CAMPAIGN/summary.csv not found" >&2; exit 2; }
slam-predict worlds import-thesis "$DATA_DIR/thesis/environments.csv" --out "$OUT/thesis_worlds" \
  --force > /dev/null
# one folder with the worlds of every building of the campaign (symlinks), named as in
# summary.csv; `learn dataset` keeps those with >= MIN_RUNS runs (--min-runs)
tail -n +2 "$CAMPAIGN/summary.csv" | cut -d, -f1 | while read -r world; do
  for candidate in "$ROOT/worlds/$world" "$OUT/thesis_worlds/$world"; do
    if [ -f "$candidate.world" ]; then
      for ext in world png json; do
        [ -f "$candidate.$ext" ] && ln -s "$candidate.$ext" "$OUT/worlds/$world.$ext"
      done
      break
    fi
  done
  [ -f "$OUT/worlds/$world.world" ] || { echo "train_own_model: no world file for $world" >&2; exit 2; }
done
# the campaign's own summary.csv, so that the card names the campaign
slam-predict learn dataset --errors "$CAMPAIGN/summary.csv" --min-runs "$MIN_RUNS" \
  --worlds "$OUT/worlds" --thesis-setting realistic \
  --out "$OUT/own-realistic.csv" --jobs "$JOBS" --force
BUILDINGS=$(($(wc -l < "$OUT/own-realistic.csv") - 1))   # one row per building
echo "[own model] $BUILDINGS buildings with >= $MIN_RUNS runs"
# --priority -1: thesis-realistic (the seed study's own errors of the same buildings) stays the
# default model
slam-predict learn train "$OUT/own-realistic.csv" --name own-realistic --models-dir "$MODELS" \
  --evaluation-out "$OUT/eval" --jobs "$JOBS" --force --priority -1 \
  --description "${DESCRIPTION:-GMapping errors collected by slam_predict itself ($(basename "$CAMPAIGN"), issue #41: in-process Stage-like simulator with Stage-style fixed odometry biases + our GMapping with slam_gmapping's compute delay (its fitted settings: the card's sources.fitted) + move_base-like navigation with a checked back-up and base_local_planner's blind escape alternating + nearest-frontier exploration, realistic setting, >= $MIN_RUNS runs per building) on $BUILDINGS seed-study buildings of every size}"
echo "[own model] models/own-realistic written; evaluation in $OUT/eval"
