#!/usr/bin/env bash
# Rebuild the shipped models models/thesis-realistic and models/thesis-optimistic from the seed
# study's measured errors (../shared/data/thesis) and OUR features computed on the thesis
# buildings that have a plan (44 of 88), as `worlds import-thesis` rebuilds them.
# Usage: tools/train_thesis_models.sh [OUT]   (intermediate files in OUT, default out/thesis_models)
# Environment: SLAM_PREDICT_SHARED (default ../shared), JOBS (default 2), MODELS (default models/).
# Takes about 15 min on a 2-core VM; the result is deterministic (seeded) for a given feature
# version and library versions.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-$ROOT/out/thesis_models}"
SHARED="${SLAM_PREDICT_SHARED:-$ROOT/../shared}"
THESIS="$SHARED/data/thesis"
JOBS="${JOBS:-2}"
MODELS="${MODELS:-$ROOT/models}"
set +u; source "$ROOT/setup.bash"; set -u
mkdir -p "$OUT"

echo "[thesis models] importing the thesis buildings into $OUT/worlds"
slam-predict worlds import-thesis "$THESIS/environments.csv" --out "$OUT/worlds" --force

echo "[thesis models] computing features (realistic dataset)"
slam-predict learn dataset --errors "$THESIS/stats_realistic.csv" --worlds "$OUT/worlds" \
  --thesis-setting realistic --save-features "$OUT/features.csv" --out "$OUT/thesis-realistic.csv" \
  --jobs "$JOBS" --force
echo "[thesis models] optimistic dataset (same features)"
slam-predict learn dataset --errors "$THESIS/stats_optimistic.csv" --features "$OUT/features.csv" \
  --thesis-setting optimistic --out "$OUT/thesis-optimistic.csv" --force

for setting in realistic optimistic; do
  echo "[thesis models] evaluating and training thesis-$setting"
  slam-predict learn train "$OUT/thesis-$setting.csv" --name "thesis-$setting" \
    --models-dir "$MODELS" --evaluation-out "$OUT/eval-$setting" --jobs "$JOBS" --force \
    --description "GMapping errors of the seed thesis (Castelli 2017, $setting setting, about 36 runs per building) on the 44 thesis buildings with a plan; features computed by slam_predict on the worlds of 'worlds import-thesis'"
done
echo "[thesis models] models in $MODELS, evaluations in $OUT/eval-*"
