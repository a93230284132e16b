#!/usr/bin/env bash
# Run (or resume) one of the project's committed data-collection campaigns.
#
#   tools/run_campaign.sh NAME [--jobs K] [--runs N] [--part fit|judge]
#
# NAME: realistic | fidelity_fixed_80 | fidelity_uniform_per_run_60 | fidelity_fixed_60 |
#       fidelity_sizes | fidelity_sizes_r2 | fidelity_seed_study | fidelity_seed_study_2 |
#       fidelity_seed_study_3 | fidelity_seed_study_4 | fidelity_seed_study_5 |
#       fidelity_seed_study_6 | fidelity_seed_study_7 | fidelity_seed_study_8 |
#       robots | robots_rep3 |
#       robots_3 | robots_3_rep3 | robots_3_rep4 | robots_3_res025 | robots_3_res100 |
#       robots_more | robots_configs2 | robots_rep4 | robots_res025 | robots_res100 |
#       fidelity_seed_study_9 | karto_seed_study | karto_robots | karto_beside_8 | karto_beside_9
#   realistic: the default settings (config/collect.yaml) on 8 small seed-study buildings
#              (built by `worlds import-thesis` from ../shared/data) + 4 shipped worlds; trains
#              the own-realistic model and is the uniform_per_run/80 m cell of the fidelity table.
#   fidelity_*: the same 8 seed-study buildings under config/fidelity/<variant>.yaml.
#   fidelity_sizes (issue #16): the 8 + 10 seed-study buildings of 1,100-6,200 m2 of free floor,
#              config/fidelity/sizes.yaml; runs are added breadth-first (run 1 of every building,
#              then run 2, ...) so that a campaign cut by the end of a working period is usable.
#   fidelity_sizes_r2 (issue #16): the same buildings under config/fidelity/sizes_rebuild2.yaml
#              (the map rebuild twice as dear per traced cell; docs/notes/fidelity.md, 2026-12-03).
#   fidelity_seed_study (issue #16): the same buildings under config/fidelity/seed_study.yaml
#              (Stage's fixed odometry biases, the calibrated compute delay): the fidelity
#              campaign whose settings the robots campaign and own-realistic use. Since
#              2026-12-05 every seed-study building with a plan (44): the buildings of its
#              parts.yaml, the 17 the compute level was fitted on and the 27 that judge it.
#   fidelity_seed_study_2 (issue #41, 2026-12-06): fidelity_seed_study's buildings, parts and
#              settings on the collection chain since aec4858 (the older campaigns predate its
#              navigation change, data/campaigns/README.md); same base seed, so a run the change
#              does not reach repeats its fidelity_seed_study record. `--part fit` collects the
#              fitted-on buildings only (the fitted setting is checked on them before any judged
#              run is collected), `--part judge` the others; judged runs (and a run of both
#              parts) are refused until the fit part has all its runs.
#   fidelity_seed_study_3 (issue #41, 2026-12-07): the same with config/fidelity/seed_study_back_up.yaml
#              (the robot backs up 0.5 m after 60 s without progress); same base seed, so a run in
#              which the back-up never fires repeats its fidelity_seed_study_2 record; same parts
#              rule (fit part first).
#   fidelity_seed_study_4 (issue #41, 2026-12-07): the same with
#              config/fidelity/seed_study_back_up_checked.yaml (the back-up checks its path in the
#              local costmap, after Nav2's BackUp); a run whose back-up never meets a wall repeats
#              its fidelity_seed_study_3 record; same parts rule (fit part first).
#   fidelity_seed_study_5 (issue #41, 2026-12-07): the same chain with config/fidelity/seed_study_refit.yaml
#              (fidelity_seed_study_4's settings, slam_gmapping's cpu_factor refitted on the fit
#              part to 0.88); same parts rule (fit part first).
#   fidelity_seed_study_6 (issue #41, 2026-12-07): config/fidelity/seed_study_refit_escape.yaml
#              (fidelity_seed_study_5's settings with base_local_planner's blind escape
#              alternating, escape_alternate); a run in which two blind escapes never follow each
#              other repeats its fidelity_seed_study_5 record; same parts rule (fit part first).
#   fidelity_seed_study_7 (issue #41, 2026-12-07): config/fidelity/seed_study_reachable.yaml
#              (fidelity_seed_study_6's settings with explore_lite's frontier search: only
#              frontiers joined to the robot's free space, explore.reachable_frontiers); same
#              parts rule (fit part first). Stopped after run 1 of the fit part: not adopted
#              (docs/notes/exploration.md, "Frontiers in free pockets inside walls").
#   fidelity_seed_study_8 (issue #41, 2026-12-07): config/fidelity/seed_study_clear_footprint.yaml
#              (base_local_planner's own rules, `upstream_rules`, and the local costmap clearing
#              the robot's footprint as costmap_2d does; docs/notes/exploration.md "Narrow doors");
#              same parts rule (fit part first).
#   fidelity_seed_study_9 (issue #41, 2026-12-07): config/fidelity/seed_study_clear_refit.yaml
#              (fidelity_seed_study_8's chain with slam_gmapping's cpu_factor refitted on its fit
#              part: 1.0); same parts rule (fit part first).
#   robots_2, robots_2_rep3, robots_2_rep4, robots_2_res025, robots_2_res100 (issue #41,
#              2026-12-07): robots, robots_rep3, ... collected again, same designs and seeds, on
#              fidelity_seed_study_6's chain (config/robot_campaign/settings_refit_escape.yaml).
#   robots_3, robots_3_rep3, robots_3_rep4, robots_3_res025, robots_3_res100 (issue #41,
#              2026-12-07): the robots campaigns' designs and seeds collected again on
#              fidelity_seed_study_9's chain (config/robot_campaign/settings_clear_refit.yaml,
#              sensor logs kept for Karto beside).
#   karto_beside_8, karto_beside_9 (issue #40, 2026-12-07): Karto (slam_toolbox's async node)
#              beside every route of fidelity_seed_study_8 (_9) that is on this machine with its
#              sensor log (the two chains differ only in GMapping's compute level)
#              (`slam-predict slam beside`, config/fidelity/seed_study_clear_footprint_karto.yaml):
#              both algorithms measured on the same routes; run it in the working period that
#              collected the routes (sensor logs are not committed).
#   karto_seed_study_2, karto_robots_2 (issues #40, #41, 2026-12-07): karto_seed_study and
#              karto_robots on fidelity_seed_study_6's chain
#              (config/fidelity/seed_study_refit_escape_karto.yaml).
#   karto_seed_study (2026-12-05): the fidelity campaign's buildings (its parts.yaml) explored by
#              the same chain with Karto as slam_toolbox's async node in real time
#              (config/fidelity/seed_study_karto.yaml), 3 runs each, breadth-first.
#   karto_robots (2026-12-06): Karto's robot-aware campaign, a declared subset of the robots
#              design that spans it: the design's first 4 runs per building (replicate 1 of each
#              of the building's 4 points: all 28 configurations, 84 runs) on robots' 21
#              buildings, with the Karto fidelity chain (config/fidelity/seed_study_karto.yaml);
#              the design replaces the laser and odometry run by run, as for robots.
#   robots (issue #18): 21 seed-study buildings of <= 2,000 m2, each explored with 4 robot
#              configurations of data/campaigns/robots/design.yaml (28 configurations, a
#              Latin hypercube over laser range, fov and odometry error), 2 runs each (168 runs),
#              settings config/robot_campaign/settings.yaml.
#   robots_rep3 (issue #18): a third replicate of every robots design point (the design's first
#              4 runs per building, --seed 3: new seeds), in its own folder; `learn robots
#              data/campaigns/robots data/campaigns/robots_rep3` pools the two.
#   robots_rep4 (issue #18, 2026-12-05): a fourth replicate, as robots_rep3 with --seed 4: less
#              run-to-run noise in every point's measured mean (pooled like robots_rep3).
#   robots_more (issue #18, 2026-12-04): the same 28 configurations on 4 more seed-study
#              buildings of 2,083-2,208 m2 (data/campaigns/robots/design_more.yaml), 4 points x
#              2 runs each, breadth-first: every building's first replicate before any second.
#   robots_configs2 (issue #18, 2026-12-04): 14 more configurations (c28-c41,
#              data/campaigns/robots/design_configs2.yaml) on robots' 21 buildings, 2 points x
#              2 runs per building (84 runs), breadth-first; pooled with robots and robots_rep3
#              it gives the configuration-held-out protocol 42 configurations instead of 28.
#   robots_res025, robots_res100 (issue #43, 2026-12-06): 7 configurations each at 0.25 and
#              1.0 deg angular resolution (data/campaigns/robots/design_res025.yaml,
#              design_res100.yaml; the robots design has 0.5 deg only), one point on each of
#              robots' 21 buildings, 2 runs, breadth-first: every building's first run first.
# Records go to data/campaigns/NAME/ (run.json and summary.csv are committed, the rest is not);
# finished runs are never redone, so the command can be repeated in every working period.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
NAME="${1:?usage: tools/run_campaign.sh NAME [--jobs K] [--runs N] [--part fit|judge] [--dry-run]}"; shift
JOBS=2; RUNS=5; PART=""; DRY_RUN=0
case "$NAME" in fidelity_sizes*|fidelity_seed_study*|karto_seed_study*) RUNS=3 ;; esac   # issue #16: >= 3 runs per building
while [ $# -gt 0 ]; do
  case "$1" in
    --jobs) JOBS="$2"; shift 2 ;;
    --runs) RUNS="$2"; shift 2 ;;
    --part) PART="$2"; shift 2 ;;
    --dry-run) DRY_RUN=1; shift ;;
    *) echo "run_campaign: unknown argument $1" >&2; exit 2 ;;
  esac
done
if [[ "$NAME" =~ ^karto_beside_[89]$ ]]; then   # a replay of the routes, not a collection
  [ -f "$ROOT/setup.bash" ] || bash "$ROOT/tools/setup.sh"
  set +u; source "$ROOT/setup.bash"; set -u
  exec slam-predict slam beside "$ROOT/data/campaigns/fidelity_seed_study_${NAME#karto_beside_}" \
    --jobs "$JOBS" --settings "$ROOT/config/fidelity/seed_study_clear_footprint_karto.yaml" \
    --out "$ROOT/data/campaigns/$NAME"
fi
THESIS_BUILDINGS="Borchen4_updated Lamuniere1_updated scuola_secondaria_i_grado_mera__updated
  Franch1_updated Sabadell3_updated Liselotte1_updated Sabadell1_updated Vipiteno2_updated"
LARGE_BUILDINGS="Ursy1_updated 324-Elm-Furn-Plan_updated office_h battle_creekhs_2_updated
  floor-1024x523_updated south_mountain_school_2_updated lab_intel Neulengbach1_updated NLB
  FALAELEM1_updated"
SHIPPED="office_150 school_300 office_500 office_800"
ROBOT_BUILDINGS="324-Elm-Furn-Plan_updated Borchen4_updated Franch1_updated Lamuniere1_updated
  Liselotte1_updated RomainRolland1_updated SKF_FloorPlan_updated Sabadell1_updated
  Sabadell3_updated Sicurezza_1_updated Ursy1_updated Valleceppi_P0_updated Valleceppi_P1_updated
  VarzeaPaulistaFDE1_updated Vipiteno2_updated battle_creekhs_2_updated floorplanMAIN_updated
  office_h scuola_sconosciuta_3_updated scuola_sconosciuta_updated
  scuola_secondaria_i_grado_mera__updated"
MORE_ROBOT_BUILDINGS="130604-Plan_updated UMTD_School_Floorplan_updated VarzeaPaulistaFDE2_updated
  executive-office-floor-plans-l-a622d60bb7a76a60_updated"
DESIGN_ARGS=()
WITH_LARGE=0
ROBOT_SETTINGS="$ROOT/config/robot_campaign/settings.yaml"
KARTO_SETTINGS="$ROOT/config/fidelity/seed_study_karto.yaml"
CAMPAIGN="$NAME"   # the *_2 campaigns: their first collection's design on fidelity_seed_study_6's chain
case "$NAME" in
  robots_2|robots_2_*) CAMPAIGN="robots${NAME#robots_2}"
          ROBOT_SETTINGS="$ROOT/config/robot_campaign/settings_refit_escape.yaml" ;;
  robots_3|robots_3_*) CAMPAIGN="robots${NAME#robots_3}"
          ROBOT_SETTINGS="$ROOT/config/robot_campaign/settings_clear_refit.yaml" ;;
  karto_seed_study_2|karto_robots_2) CAMPAIGN="${NAME%_2}"
          KARTO_SETTINGS="$ROOT/config/fidelity/seed_study_refit_escape_karto.yaml" ;;
esac
case "$CAMPAIGN" in
  realistic) SETTINGS="$ROOT/config/collect.yaml"; WITH_SHIPPED=1 ;;
  fidelity_fixed_80) SETTINGS="$ROOT/config/fidelity/fixed_80.yaml"; WITH_SHIPPED=0 ;;
  fidelity_uniform_per_run_60) SETTINGS="$ROOT/config/fidelity/uniform_per_run_60.yaml"; WITH_SHIPPED=0 ;;
  fidelity_fixed_60) SETTINGS="$ROOT/config/fidelity/fixed_60.yaml"; WITH_SHIPPED=0 ;;
  fidelity_sizes) SETTINGS="$ROOT/config/fidelity/sizes.yaml"; WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_sizes_r2) SETTINGS="$ROOT/config/fidelity/sizes_rebuild2.yaml"; WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study_3) SETTINGS="$ROOT/config/fidelity/seed_study_back_up.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study_4) SETTINGS="$ROOT/config/fidelity/seed_study_back_up_checked.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study_5) SETTINGS="$ROOT/config/fidelity/seed_study_refit.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study_6) SETTINGS="$ROOT/config/fidelity/seed_study_refit_escape.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study_8) SETTINGS="$ROOT/config/fidelity/seed_study_clear_footprint.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study_9) SETTINGS="$ROOT/config/fidelity/seed_study_clear_refit.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study_7) SETTINGS="$ROOT/config/fidelity/seed_study_reachable.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  fidelity_seed_study|fidelity_seed_study_2) SETTINGS="$ROOT/config/fidelity/seed_study.yaml"
          WITH_SHIPPED=0; WITH_LARGE=1 ;;
  karto_seed_study) SETTINGS="$KARTO_SETTINGS"; WITH_SHIPPED=0; WITH_LARGE=1 ;;
  karto_robots) SETTINGS="$KARTO_SETTINGS"; WITH_SHIPPED=0
          DESIGN_ARGS=(--design "$ROOT/data/campaigns/robots/design.yaml" --runs 4) ;;
  robots) SETTINGS="$ROBOT_SETTINGS"; WITH_SHIPPED=0
          DESIGN_ARGS=(--design "$ROOT/data/campaigns/robots/design.yaml") ;;
  robots_rep3|robots_rep4) SETTINGS="$ROBOT_SETTINGS"; WITH_SHIPPED=0
          # replicate k: the design's first 4 runs per building under --seed k
          DESIGN_ARGS=(--design "$ROOT/data/campaigns/robots/design.yaml" --runs 4
                       --seed "${CAMPAIGN#robots_rep}") ;;
  robots_more) SETTINGS="$ROBOT_SETTINGS"; WITH_SHIPPED=0
          DESIGN_ARGS=(--design "$ROOT/data/campaigns/robots/design_more.yaml") ;;
  robots_configs2) SETTINGS="$ROBOT_SETTINGS"; WITH_SHIPPED=0
          DESIGN_ARGS=(--design "$ROOT/data/campaigns/robots/design_configs2.yaml") ;;
  robots_res025|robots_res100) SETTINGS="$ROBOT_SETTINGS"
          WITH_SHIPPED=0
          DESIGN_ARGS=(--design "$ROOT/data/campaigns/robots/design_${CAMPAIGN#robots_}.yaml") ;;
  *) echo "run_campaign: unknown campaign '$NAME' (realistic, fidelity_fixed_80, fidelity_uniform_per_run_60, fidelity_fixed_60, fidelity_sizes, fidelity_sizes_r2, fidelity_seed_study, fidelity_seed_study_2, fidelity_seed_study_3, fidelity_seed_study_4, fidelity_seed_study_5, fidelity_seed_study_6, fidelity_seed_study_7, fidelity_seed_study_8, fidelity_seed_study_9, robots, robots_rep3, robots_more, robots_configs2, robots_rep4, robots_res025, robots_res100, karto_seed_study, karto_robots; robots_2, robots_2_rep3, robots_2_rep4, robots_2_res025, robots_2_res100, robots_3, robots_3_rep3, robots_3_rep4, robots_3_res025, robots_3_res100, karto_seed_study_2, karto_robots_2)" >&2; exit 2 ;;
esac
case "$PART" in
  "") ;;
  fit|judge) case "$CAMPAIGN" in fidelity_seed_study*|karto_seed_study) ;;
               *) echo "run_campaign: --part only applies to the campaigns with parts.yaml" >&2
                  exit 2 ;;
             esac ;;
  *) echo "run_campaign: --part must be fit or judge, got '$PART'" >&2; exit 2 ;;
esac
PARTS_YAML="$ROOT/data/campaigns/fidelity_seed_study/parts.yaml"
part_buildings() {   # the buildings of one declared part of PARTS_YAML ("": every part)
  python3 -c 'import sys, yaml
parts = yaml.safe_load(open(sys.argv[1]))["parts"]
print(" ".join(w for name, part in parts.items() if sys.argv[2] in ("", name) for w in part))' \
    "$PARTS_YAML" "$1"
}
if [[ "$NAME" =~ ^fidelity_seed_study_[0-9]+$ ]] && [ "$PART" != fit ]; then
  # the declared order: the fitted setting is checked on the whole fit part before any judged run
  FIT_DONE=0; FIT_WANTED=0
  for b in $(part_buildings fit); do
    FIT_WANTED=$((FIT_WANTED + RUNS))
    n=$( (find "$ROOT/data/campaigns/$NAME/$b" -name run.json 2>/dev/null || true) | wc -l)
    FIT_DONE=$((FIT_DONE + (n < RUNS ? n : RUNS)))
  done
  if [ "$FIT_DONE" -lt "$FIT_WANTED" ]; then
    echo "run_campaign: $NAME: the fit part has $FIT_DONE of its $FIT_WANTED runs; collect it first (--part fit)" >&2
    exit 2
  fi
fi
BUILDINGS="$THESIS_BUILDINGS"
[ "$WITH_LARGE" = 1 ] && BUILDINGS="$THESIS_BUILDINGS $LARGE_BUILDINGS"
case "$CAMPAIGN" in
  fidelity_seed_study*|karto_seed_study)   # the fidelity campaign's parts: fitted-on, then judged
    BUILDINGS="$(part_buildings "$PART")" ;;
  robots_more) BUILDINGS="$MORE_ROBOT_BUILDINGS" ;;
  robots*|karto_robots) BUILDINGS="$ROBOT_BUILDINGS" ;;
esac
if [ "$DRY_RUN" = 1 ]; then   # what would be collected, and with which settings; nothing is run
  echo "campaign: $NAME"
  echo "settings: ${SETTINGS#"$ROOT/"}"
  [ "${#DESIGN_ARGS[@]}" -gt 0 ] && echo "design: ${DESIGN_ARGS[*]//"$ROOT/"/}"
  echo "buildings ($(wc -w <<< "$BUILDINGS")): $(tr -s ' \n' ' ' <<< "$BUILDINGS" | sed 's/^ //; s/ $//')"
  exit 0
fi
DATA_DIR="${SLAM_PREDICT_DATA:-$ROOT/../shared/data}"
if [ ! -f "$DATA_DIR/thesis/environments.csv" ]; then
  echo "run_campaign: $DATA_DIR/thesis/environments.csv not found (set SLAM_PREDICT_DATA)" >&2; exit 2
fi
[ -f "$ROOT/setup.bash" ] || bash "$ROOT/tools/setup.sh"
set +u; source "$ROOT/setup.bash"; set -u
WORLDS_DIR="$ROOT/out/thesis_worlds"
# shellcheck disable=SC2086
slam-predict worlds import-thesis "$DATA_DIR/thesis/environments.csv" --out "$WORLDS_DIR" \
  --force --only $BUILDINGS > /dev/null
WORLDS=()
for b in $BUILDINGS; do WORLDS+=("$WORLDS_DIR/$b.world"); done
if [ "$WITH_SHIPPED" = 1 ]; then
  for w in $SHIPPED; do WORLDS+=("$ROOT/worlds/$w.world"); done
fi
if [ "$WITH_LARGE" = 1 ]; then   # breadth-first: every building's run k before any run k+1
  for ((k = 1; k < RUNS; k++)); do
    slam-predict collect "${WORLDS[@]}" --runs "$k" --jobs "$JOBS" \
      --settings "$SETTINGS" --out "$ROOT/data/campaigns/$NAME"
  done
fi
if [ "$CAMPAIGN" = robots_more ]; then   # breadth-first: the first replicate of every building first
  slam-predict collect "${WORLDS[@]}" "${DESIGN_ARGS[@]}" --runs 4 --jobs "$JOBS" \
    --settings "$SETTINGS" --out "$ROOT/data/campaigns/$NAME"
fi
case "$CAMPAIGN" in robots_res*)   # breadth-first: every building's first run first
  slam-predict collect "${WORLDS[@]}" "${DESIGN_ARGS[@]}" --runs 1 --jobs "$JOBS" \
    --settings "$SETTINGS" --out "$ROOT/data/campaigns/$NAME" ;;
esac
if [ "$CAMPAIGN" = robots_configs2 ]; then   # breadth-first: each building's 2 points once first
  slam-predict collect "${WORLDS[@]}" "${DESIGN_ARGS[@]}" --runs 2 --jobs "$JOBS" \
    --settings "$SETTINGS" --out "$ROOT/data/campaigns/$NAME"
fi
if [ "${#DESIGN_ARGS[@]}" -gt 0 ]; then   # the design sets the runs (all, or --runs in DESIGN_ARGS)
  exec slam-predict collect "${WORLDS[@]}" "${DESIGN_ARGS[@]}" --jobs "$JOBS" \
    --settings "$SETTINGS" --out "$ROOT/data/campaigns/$NAME"
fi
exec slam-predict collect "${WORLDS[@]}" --runs "$RUNS" --jobs "$JOBS" \
  --settings "$SETTINGS" --out "$ROOT/data/campaigns/$NAME"
