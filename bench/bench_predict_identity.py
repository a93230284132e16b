#!/usr/bin/env python3
"""No-behaviour-change check for the learning code: ``predict --json`` (and optionally the
thesis models' training and a campaign report) on two code trees, compared byte for byte.

The reference tree is ``git archive REF`` unpacked into a cache folder; its outputs are kept
(``OUT/ref-<sha>/``), so later runs only recompute this tree's. Both trees run with this
tree's ``.venv`` interpreter and their own ``src/`` first on ``PYTHONPATH``, each with its
own ``models/``.

    python bench/bench_predict_identity.py --ref e99e84b              # predict cases
    python bench/bench_predict_identity.py --ref e99e84b --thesis     # + thesis training
    python bench/bench_predict_identity.py --ref e99e84b --report     # + campaign report

Predict cases: 10 plans (the shipped worlds and ipa plans at 0.05 m/px) with every plan-only
model, the ``best`` model in both settings, and with ``--robot`` every robot file on some
plan (every plan gets at least one). Thesis: ``learn dataset`` from the reference tree's
features of the imported thesis buildings (computed once), then ``learn train`` of both
settings; every output file is compared except the card's creation time. The report's
generation time is masked. Exit code 0 when every output is identical, 1 otherwise (the
differing cases are printed).
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("SLAM_PREDICT_SHARED", ROOT.parent / "shared"))
WORLDS = ["tiny", "office_150", "office_500", "school_300", "school_1000", "office_1500"]
IPA = ["lab_a_scan", "lab_b_scan", "lab_c_scan", "Freiburg79_scan"]
PLAN_MODELS = ["thesis-realistic", "thesis-optimistic", "own-realistic"]
ROBOTS = ["lds_360_3p5", "seed_optimistic", "seed_realistic", "seed_realistic_fixed",
          "urg_240_5p6", "utm_270_30_poor_odom"]
REPORT_CAMPAIGN = "data/campaigns/fidelity_seed_study"
VOLATILE_CARD_KEYS = ("created",)

# One process per case, one BLAS thread, and ARPACK's start vector seeded: scipy's eigsh
# draws it from OS entropy when given no rng, so the eigenvector centrality of a Voronoi graph
# of more than 50 nodes (features/graph_metrics.py) differs from run to run in its last
# digits (about 1e-13 relative), and so does every prediction that reads it.
THREADS = {k: "1" for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                           "NUMBA_NUM_THREADS")}
SEEDED_ARPACK = """
import functools
import numpy as np
import scipy.sparse.linalg as splinalg
_eigsh = splinalg.eigsh
@functools.wraps(_eigsh)
def eigsh(*args, **kwargs):
    if kwargs.get("v0") is None and kwargs.get("rng") is None:
        kwargs["rng"] = np.random.default_rng(0)
    return _eigsh(*args, **kwargs)
splinalg.eigsh = eigsh
"""


def plans() -> list[tuple[str, list[str]]]:
    """(name, plan arguments) of the 10 plans."""
    out = [(w, [str(ROOT / "worlds" / f"{w}.world")]) for w in WORLDS]
    for name in IPA:
        png = SHARED / "data" / "floorplans" / "ipa" / f"{name}.png"
        if png.is_file():
            out.append((name, [str(png), "--resolution", "0.05"]))
    return out


def predict_cases(tree: Path) -> list[tuple[str, list[str]]]:
    """(case name, CLI argv) of every predict case, paths inside ``tree``."""
    models = ["--models-dir", str(tree / "models"), "--json"]
    cases = []
    for i, (plan, args) in enumerate(plans()):
        for model in PLAN_MODELS:
            cases.append((f"{plan}:{model}", ["predict", *args, "--model", model, *models]))
        cases.append((f"{plan}:best-optimistic",
                      ["predict", *args, "--setting", "optimistic", *models]))
        robots = ROBOTS if i == 0 else [ROBOTS[i % len(ROBOTS)]]
        for robot in robots:
            cases.append((f"{plan}:robot:{robot}",
                          ["predict", *args, "--robot",
                           str(tree / "config" / "robots" / f"{robot}.yaml"), *models]))
    cases.append(("tiny:robot-with-plan-model",
                  ["predict", str(tree / "worlds" / "tiny.world"), "--robot",
                   str(tree / "config" / "robots" / "seed_realistic.yaml"),
                   "--model", "thesis-realistic", *models]))
    return cases


def run_python(tree: Path, args: list[str], cwd: Path,
               check: bool = True) -> subprocess.CompletedProcess:
    pin = Path(tempfile.gettempdir()) / "slam_predict_identity_pin"
    pin.mkdir(exist_ok=True)
    (pin / "sitecustomize.py").write_text(SEEDED_ARPACK)
    env = dict(os.environ, PYTHONPATH=f"{tree / 'src'}{os.pathsep}{pin}",
               SLAM_PREDICT_MODELS=str(tree / "models"), **THREADS)
    return subprocess.run(["nice", str(ROOT / ".venv" / "bin" / "python"), *args], cwd=cwd,
                          env=env, check=check, capture_output=not check, text=True)


def run_cli(tree: Path, argv: list[str], cwd: Path) -> None:
    run_python(tree, ["-m", "slam_predict.cli.main", *argv], cwd)


def normalised(text: str, tree: Path) -> str:
    """Output text with the tree's path replaced by a placeholder."""
    return text.replace(str(tree), "<TREE>")


def run_predict(tree: Path, folder: Path) -> dict:
    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for name, argv in predict_cases(tree):
        done = run_python(tree, ["-m", "slam_predict.cli.main", *argv], folder, check=False)
        out[name] = {"exit": str(done.returncode), "stdout": normalised(done.stdout, tree),
                     "stderr": normalised(done.stderr, tree)}
    return out


def thesis_features(ref: Path, cache: Path) -> Path:
    """Features of the imported thesis buildings, computed once with the reference tree."""
    features = cache / "thesis_features.csv"
    if not features.is_file():
        worlds = cache / "thesis_worlds"
        thesis = SHARED / "data" / "thesis"
        run_cli(ref, ["worlds", "import-thesis", str(thesis / "environments.csv"),
                      "--out", str(worlds), "--force"], cache)
        run_cli(ref, ["learn", "dataset", "--errors", str(thesis / "stats_realistic.csv"),
                      "--worlds", str(worlds), "--setting", "realistic", "--save-features",
                      str(features), "--out", str(cache / "unused.csv"), "--jobs", "1",
                      "--force"], cache)
    return features


def run_thesis(tree: Path, folder: Path, features: Path) -> dict:
    """The files ``learn dataset`` + ``learn train`` write for both thesis settings."""
    thesis = SHARED / "data" / "thesis"
    folder.mkdir(parents=True, exist_ok=True)
    for setting in ("realistic", "optimistic"):
        data = folder / f"thesis-{setting}.csv"
        run_cli(tree, ["learn", "dataset", "--errors", str(thesis / f"stats_{setting}.csv"),
                       "--features", str(features), "--setting", setting, "--out", str(data),
                       "--force"], folder)
        run_cli(tree, ["learn", "train", str(data), "--name", f"thesis-{setting}",
                       "--models-dir", str(folder / "models"), "--evaluation-out",
                       str(folder / f"eval-{setting}"), "--jobs", "1", "--force"], folder)
    return files_of(folder, tree)


def run_report(tree: Path, folder: Path) -> dict:
    folder.mkdir(parents=True, exist_ok=True)
    run_cli(tree, ["report", str(tree / REPORT_CAMPAIGN), "--models", str(tree / "models"),
                   "--out", str(folder / "report.html"), "--force"], folder)
    return {"report.html": normalised((folder / "report.html").read_text(), tree)}


def files_of(folder: Path, tree: Path) -> dict:
    """{relative path: content} of every file under ``folder`` (cards without volatile keys)."""
    out = {}
    for path in sorted(p for p in folder.rglob("*") if p.is_file()):
        rel = str(path.relative_to(folder))
        if path.name == "card.json":
            card = json.loads(path.read_text())
            for key in VOLATILE_CARD_KEYS:
                card.pop(key, None)
            out[rel] = normalised(json.dumps(card, indent=1), tree)
        else:
            data = path.read_bytes()
            try:
                out[rel] = normalised(data.decode(), tree)
            except UnicodeDecodeError:
                out[rel] = data.hex()
    return out


def reference_tree(ref: str, cache: Path) -> tuple[Path, str]:
    sha = subprocess.run(["git", "-C", str(ROOT), "rev-parse", ref], check=True,
                         capture_output=True, text=True).stdout.strip()
    tree = cache / f"tree-{sha[:12]}"
    if not (tree / "src").is_dir():
        tree.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile() as tar:
            subprocess.run(["git", "-C", str(ROOT), "archive", sha], stdout=tar, check=True)
            tar.seek(0)
            with tarfile.open(fileobj=tar) as archive:
                archive.extractall(tree)  # noqa: S202 — our own commit
    return tree, sha[:12]


def outputs(tree: Path, folder: Path, args, features: Path | None, reuse: bool) -> dict:
    """{part: {case: output}} for one tree (read from ``folder`` when ``reuse`` and present)."""
    saved = folder / "outputs.json"
    result = json.loads(saved.read_text()) if reuse and saved.is_file() else {}
    start = time.process_time()
    if "predict" not in result:
        result["predict"] = run_predict(tree, folder / "predict")
    if args.thesis and "thesis" not in result:
        result["thesis"] = run_thesis(tree, folder / "thesis", features)
    if args.report and "report" not in result:
        result["report"] = run_report(tree, folder / "report")
    folder.mkdir(parents=True, exist_ok=True)
    saved.write_text(json.dumps(result))
    ru = os.times()
    print(f"{tree}: outputs ready (children CPU {ru.children_user + ru.children_system:.0f} s, "
          f"own {time.process_time() - start:.1f} s)")
    return result


def masked(value):
    """An output with the report's generation time masked."""
    if not isinstance(value, str):
        return value
    return re.sub(r"Generated \d{4}-\d\d-\d\d \d\d:\d\d UTC", "Generated <TIME>", value)


def compare(ref: dict, new: dict) -> list[str]:
    problems = []
    for part in sorted(set(ref) & set(new)):
        for case in sorted(set(ref[part]) | set(new[part])):
            if masked(ref[part].get(case)) != masked(new[part].get(case)):
                problems.append(f"{part}: {case} differs")
    return problems


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="e99e84b", help="reference commit (default e99e84b)")
    parser.add_argument("--new", default=str(ROOT), help="tree to check (default: this one)")
    parser.add_argument("--out", default=str(ROOT / "out" / "identity"),
                        help="cache and output folder (default out/identity)")
    parser.add_argument("--thesis", action="store_true", help="also train the thesis models")
    parser.add_argument("--report", action="store_true", help="also write a campaign report")
    parser.add_argument("--show", metavar="CASE", help="print both outputs of one case")
    args = parser.parse_args()
    cache = Path(args.out).resolve()
    ref_tree, sha = reference_tree(args.ref, cache)
    features = thesis_features(ref_tree, cache) if args.thesis else None
    ref = outputs(ref_tree, cache / f"ref-{sha}", args, features, reuse=True)
    new_tree = Path(args.new).resolve()
    new = outputs(new_tree, cache / f"new-{new_tree.name}", args, features, reuse=False)
    if args.show:
        for side in (ref, new):
            print(json.dumps(side["predict"].get(args.show), indent=1))
    problems = compare(ref, new)
    count = sum(len(v) for v in ref.values())
    print(f"{count} outputs compared with {sha}: " + ("identical" if not problems else
                                                       f"{len(problems)} differ"))
    for line in problems:
        print("  " + line)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
