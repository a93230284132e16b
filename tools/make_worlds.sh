#!/usr/bin/env bash
# Regenerate the shipped generated worlds in worlds/ (exactly: the generator is deterministic
# from its seed). Usage: bash tools/make_worlds.sh [OUT_DIR]   (default: worlds/)
# Each line: name, kind, requested free area (m²), seed. See worlds/README.md.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${1:-$ROOT/worlds}"
set +u; source "$ROOT/setup.bash"; set -u
while read -r name kind area seed; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  slam-predict worlds generate --kind "$kind" --area "$area" --seed "$seed" \
      --resolution 0.05 --name "$name" --out "$OUT" --force
done <<'LIST'
# name        kind    area  seed
tiny          office  80    1
office_150    office  150   2
school_300    school  300   1
office_500    office  500   2
office_800    office  800   1
school_1000   school  1000  3
office_1500   office  1500  4
school_2500   school  2500  1
office_3000   office  3000  2
school_6000   school  6000  1
LIST
