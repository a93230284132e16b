#!/usr/bin/env bash
# `make demo`: the main job on a shipped world. Outputs go under $1 (default out/demo).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-$ROOT/out/demo}"
set +u; source "$ROOT/setup.bash"; set -u
mkdir -p "$OUT"
WORLD="$ROOT/worlds/office_500.world"
echo "[demo] validating and rendering $WORLD"
slam-predict worlds validate "$WORLD"
slam-predict worlds show "$WORLD" --out "$OUT/office_500_preview.png"
echo "[demo] outputs in $OUT"
