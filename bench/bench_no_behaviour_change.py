#!/usr/bin/env python3
"""No-behaviour-change check for refactors: the same (world, seed) runs on two code trees.

Runs a fixed list of closed-loop cases (``explore`` with the perfect map and with GMapping, tiny
to office_1500, and one ``collect`` run with sensor logs) with the code of a reference commit and
with the code of a work tree, then compares every output: JSON fields (except wall-clock timings
and the code version) and the bytes of every other file (maps, trajectories, sensor logs).

    python bench/bench_no_behaviour_change.py --ref 64acece            # this tree vs 64acece
    python bench/bench_no_behaviour_change.py --ref 64acece --new ../other-checkout --cases quick
    python bench/bench_no_behaviour_change.py --ref 64acece --renames renames.json

``--renames`` is a JSON object {"old.key.path": "new.key.path"} applied to the reference's JSON
files before comparing (key renames are allowed by issue #17). The explorer strategy and the
odometry model of every case are pinned, so a later change of a default does not break the check.
Exit code 0 when every case is identical, 1 otherwise (the differences are printed).
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IGNORED_KEYS = {"wall_time_s", "timing", "code_version", "created", "settings_file", "source",
                "world_file", "history", "elapsed_s", "timings", "wall_s", "timing_s",
                "timing_share", "settings_sha256", "files"}

# (name, world, map source, seed, max sim time s, strategy[, base settings]); a "collect" case
# runs one run. A world that is not in worlds/ is a seed-study building, imported from
# ../shared/data into out/thesis_worlds (`worlds import-thesis`) once and used by both trees.
CASES = [
    ("tiny_perfect", "tiny", "perfect", 1, 600, "nearest"),
    ("tiny_gmapping", "tiny", "gmapping", 2, 300, "nearest"),
    ("office_150_perfect_thesis", "office_150", "perfect", 3, 400, "thesis"),
    ("office_500_gmapping", "office_500", "gmapping", 4, 300, "nearest"),
    ("office_1500_perfect", "office_1500", "perfect", 5, 600, "nearest"),
    ("office_1500_gmapping", "office_1500", "gmapping", 6, 200, "nearest"),
    ("school_300_perfect_explore_lite", "school_300", "perfect", 7, 400, "explore_lite"),
    ("collect_office_150", "office_150", "collect", 8, 300, "nearest"),
    ("collect_lab_intel_seed_study", "lab_intel", "collect", 9, 900, "nearest",
     "config/fidelity/seed_study.yaml"),
    ("collect_vipiteno2_clear_refit", "Vipiteno2_updated", "collect", 10, 600, "thesis",
     "config/fidelity/seed_study_clear_refit.yaml"),   # base_local_planner's own rules
    ("collect_lab_intel_clear_refit", "lab_intel", "collect", 11, 600, "thesis",
     "config/fidelity/seed_study_clear_refit.yaml"),   # the same rules on a large building
]
QUICK = {"tiny_perfect", "tiny_gmapping", "collect_office_150"}


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", required=True, help="reference commit (git rev)")
    parser.add_argument("--new", default=str(ROOT), help="work tree to check (default: this one)")
    parser.add_argument("--cases", default="all", help="all | quick | comma-separated names")
    parser.add_argument("--renames", help="JSON file {old.key.path: new.key.path}")
    parser.add_argument("--keep", help="keep both output trees in this folder")
    parser.add_argument("--parallel", action="store_true",
                        help="run the two sides of a case at the same time (2 cores)")
    return parser.parse_args(argv)


def selected_cases(spec: str) -> list[tuple]:
    if spec == "all":
        return CASES
    names = QUICK if spec == "quick" else set(spec.split(","))
    unknown = names - {c[0] for c in CASES}
    if unknown:
        raise SystemExit(f"unknown case(s): {', '.join(sorted(unknown))}")
    return [c for c in CASES if c[0] in names]


def collect_settings(tree: Path, folder: Path, max_sim_time: float, strategy: str,
                     base_settings: str = "config/collect.yaml") -> Path:
    """A collect.yaml extending the tree's ``base_settings``, with a short stop rule and pinned
    defaults."""
    explore = folder / "explore.yaml"
    base = (tree / "config" / "explore.yaml").read_text()
    lines = [ln for ln in base.splitlines() if not ln.startswith("strategy:")]
    explore.write_text("\n".join([f"strategy: {strategy}"] + lines) + "\n")
    settings = folder / "collect.yaml"
    settings.write_text(
        f"extends: {tree / base_settings}\n"
        f"explore: {explore}\n"
        "sensor_logs: true\n"
        "stop:\n"
        f"  max_sim_time_s: {max_sim_time}\n"
        "  interval_s: 120.0\n"
        "  small_interval_s: 60.0\n"
        "sim_overrides: {odom: {model: uniform_per_run}}\n")
    return settings


def world_path(tree: Path, world: str) -> Path:
    """The tree's shipped world, else the seed-study building imported into this tree's
    out/thesis_worlds (the same file for both trees)."""
    shipped = tree / "worlds" / f"{world}.world"
    if shipped.is_file():
        return shipped
    imported = ROOT / "out" / "thesis_worlds" / f"{world}.world"
    if not imported.is_file():
        table = ROOT.parent / "shared" / "data" / "thesis" / "environments.csv"
        staging = imported.parent / f".import-{world}"   # import-thesis wants a new folder
        shutil.rmtree(staging, ignore_errors=True)
        subprocess.run([sys.executable, "-m", "slam_predict.cli.main", "worlds", "import-thesis",
                        str(table), "--out", str(staging), "--only", world],
                       cwd=ROOT, check=True, capture_output=True,
                       env=dict(os.environ, PYTHONPATH=str(ROOT / "src")))
        for item in staging.iterdir():
            item.replace(imported.parent / item.name)
        staging.rmdir()
    return imported


def run_case(tree: Path, case: tuple, out: Path) -> float:
    """Run one case with the code of ``tree``; returns its wall time, s."""
    name, world, source, seed, max_sim, strategy = case[:6]
    env = dict(os.environ, PYTHONPATH=str(tree / "src"),
               NUMBA_CACHE_DIR=str(tree / ".numba_cache"))
    world_file = world_path(tree, world)
    cmd = [sys.executable, "-m", "slam_predict.cli.main"]
    if source == "collect":
        work = out.parent / f"{name}.settings"
        work.mkdir(parents=True, exist_ok=True)
        settings = collect_settings(tree, work, max_sim, strategy, *case[6:])
        cmd += ["collect", str(world_file), "--out", str(out), "--runs", "1", "--seed",
                str(seed), "--settings", str(settings), "--no-progress", "--jobs", "1"]
    else:
        cmd += ["explore", str(world_file), "--map-source", source, "--seed", str(seed),
                "--out", str(out), "--max-sim-time", str(max_sim), "--strategy", strategy]
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{name} failed in {tree}:\n{proc.stderr[-2000:]}")
    return time.perf_counter() - start


def flatten(value, prefix: str = "") -> dict[str, object]:
    """JSON value -> {dotted.key.path: leaf}, without the ignored keys."""
    if isinstance(value, dict):
        flat: dict[str, object] = {}
        for key, item in value.items():
            if key in IGNORED_KEYS:
                continue
            flat.update(flatten(item, f"{prefix}{key}."))
        return flat
    return {prefix.rstrip("."): value}


def renamed(flat: dict[str, object], renames: dict[str, str]) -> dict[str, object]:
    out = {}
    for key, value in flat.items():
        for old, new in renames.items():
            if key == old or key.startswith(old + "."):
                key = new + key[len(old):]
                break
        out[key] = value
    return out


def compare_file(ref: Path, new: Path, renames: dict[str, str]) -> list[str]:
    if ref.suffix == ".json":
        a = renamed(flatten(json.loads(ref.read_text())), renames)
        b = flatten(json.loads(new.read_text()))
        diffs = [f"{k}: {a.get(k, '<absent>')!r} -> {b.get(k, '<absent>')!r}"
                 for k in sorted(set(a) | set(b)) if a.get(k, "<absent>") != b.get(k, "<absent>")]
        return diffs[:20]
    if ref.suffix == ".csv":
        return [] if _csv_rows(ref) == _csv_rows(new) else ["rows differ"]
    return [] if _content(ref) == _content(new) else ["bytes differ"]


def _content(path: Path) -> bytes:
    """The file's bytes; a .gz file's uncompressed bytes (its header holds a time stamp)."""
    if path.suffix == ".gz":
        import gzip
        return _without_version(gzip.decompress(path.read_bytes()))
    return path.read_bytes()


def _without_version(data: bytes) -> bytes:
    """A text log without its header comments that name the code version."""
    lines = data.split(b"\n")
    return b"\n".join(ln for ln in lines if not (ln.startswith(b"#") and b"slam_predict" in ln))


def _csv_rows(path: Path) -> list[list[str]]:
    """CSV rows without wall-time columns."""
    import csv
    with path.open() as fh:
        rows = list(csv.reader(fh))
    if not rows:
        return rows
    keep = [i for i, col in enumerate(rows[0]) if "wall" not in col]
    return [[row[i] for i in keep if i < len(row)] for row in rows]


def compare_trees(ref: Path, new: Path, renames: dict[str, str]) -> list[str]:
    problems = []
    ref_files = {p.relative_to(ref) for p in ref.rglob("*") if p.is_file()}
    new_files = {p.relative_to(new) for p in new.rglob("*") if p.is_file()}
    for rel in sorted(ref_files ^ new_files):
        problems.append(f"{rel}: only in {'ref' if rel in ref_files else 'new'}")
    for rel in sorted(ref_files & new_files):
        if rel.suffix == ".log" and rel.name.startswith("collect"):
            continue  # the campaign log carries timestamps
        if rel.name == ".collect.lock":
            continue  # the collecting process's id
        problems += [f"{rel}: {d}" for d in compare_file(ref / rel, new / rel, renames)]
    return problems


def main(argv: Sequence[str]) -> int:
    args = parse_args(argv)
    renames = json.loads(Path(args.renames).read_text()) if args.renames else {}
    cases = selected_cases(args.cases)
    new_tree = Path(args.new).resolve()
    work = Path(args.keep).resolve() if args.keep else Path(tempfile.mkdtemp(prefix="nbc_"))
    ref_tree = work / "ref_tree"
    if ref_tree.exists():
        subprocess.run(["git", "worktree", "remove", "--force", str(ref_tree)], cwd=ROOT)
    subprocess.run(["git", "worktree", "add", "--detach", str(ref_tree), args.ref], cwd=ROOT,
                   check=True, capture_output=True)
    failed = 0
    try:
        for case in cases:
            name = case[0]
            outs = {side: work / side / name for side in ("ref", "new")}
            for out in outs.values():
                shutil.rmtree(out, ignore_errors=True)
                out.parent.mkdir(parents=True, exist_ok=True)
            if args.parallel:
                from concurrent.futures import ThreadPoolExecutor
                world_path(new_tree, case[1])   # import it once, before both sides look for it
                with ThreadPoolExecutor(2) as pool:
                    ref_job = pool.submit(run_case, ref_tree, case, outs["ref"])
                    new_job = pool.submit(run_case, new_tree, case, outs["new"])
                    t_ref, t_new = ref_job.result(), new_job.result()
            else:
                t_ref = run_case(ref_tree, case, outs["ref"])
                t_new = run_case(new_tree, case, outs["new"])
            problems = compare_trees(outs["ref"], outs["new"], renames)
            verdict = "identical" if not problems else f"DIFFERENT ({len(problems)})"
            print(f"{name:34s} {verdict:16s} wall ref {t_ref:6.1f} s, new {t_new:6.1f} s")
            for problem in problems[:30]:
                print(f"    {problem}")
            failed += bool(problems)
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", str(ref_tree)], cwd=ROOT,
                       capture_output=True)
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    print(f"{len(cases) - failed} identical, {failed} different")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
