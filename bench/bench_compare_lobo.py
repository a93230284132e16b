"""`predict --compare` against measurements, leaving each building out of both models.

Two datasets of the same buildings (``learn dataset`` of a GMapping and of a Karto campaign of
the same chain, seed robot) are joined on the building. For every building the two algorithms'
plan-only models (per dataset, the model ``learn train`` would choose for ε_t: the highest mean
test R² over the configured repeated splits, on all buildings) are refitted without it, with
their CV+ conformal intervals (config/learning.yaml), and
:func:`slam_predict.learn.compare.decide` makes the call that ``predict --compare`` makes. It is
scored on the buildings whose two measured mean ε_t differ by more than ``--min-difference``
(20 %, relative to the lower): the share where the call names the measured better algorithm
("too close to call" counts as not naming it). Also printed: each model's leave-one-out median
percentage error of ε_t and its 90 % interval coverage.

    python bench/bench_compare_lobo.py --gmapping out/g.csv --karto out/k.csv
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from slam_predict.learn.compare import DECIDING_COMPONENT, decide  # noqa: E402
from slam_predict.learn.config import LearningConfig, load_section  # noqa: E402
from slam_predict.learn.dataset import read_dataset  # noqa: E402
from slam_predict.learn.evaluate import (  # noqa: E402
    best_models,
    evaluate_splits,
    loo_one,
    summarize,
)


def chosen_model(data, config: LearningConfig) -> str | None:
    """The ε_t model ``learn train`` would choose on ``data`` (None: no model's mean test R²
    is above 0, so ``learn train`` would ship none)."""
    summary = summarize(evaluate_splits(data, config, components=[DECIDING_COMPONENT]))
    return best_models(summary).get(DECIDING_COMPONENT)


def lobo(data, config: LearningConfig, model_id: str) -> dict[str, dict]:
    """Building → leave-one-out ε_t prediction row (:func:`loo_one`)."""
    return {row["world"]: row for row in (loo_one(data, config, DECIDING_COMPONENT, model_id, i)
                                          for i in range(len(data)))}


def entry(row: dict) -> dict:
    return {"status": "ok", "value": row["prediction"], "low": row["low"], "high": row["high"]}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gmapping", required=True, help="dataset CSV of the GMapping campaign")
    ap.add_argument("--karto", required=True, help="dataset CSV of the Karto campaign")
    ap.add_argument("--config", default=str(ROOT / "config" / "learning.yaml"))
    ap.add_argument("--min-difference", type=float, default=0.2,
                    help="relative difference of the measured ε_t that makes a pair count")
    args = ap.parse_args(argv)
    config = load_section(LearningConfig, args.config, "learning")
    sets = {"gmapping": read_dataset(args.gmapping), "karto": read_dataset(args.karto)}
    common = sorted(set(sets["gmapping"].worlds) & set(sets["karto"].worlds))
    rows = {}
    for name, data in sets.items():
        data = data.subset([data.worlds.index(w) for w in common])
        model_id = chosen_model(data, config)
        if model_id is None:
            print(f"{name}: {len(common)} buildings, no ε_t model beats the training mean "
                  f"(mean test R² ≤ 0 for every model): no call can be made")
            return 1
        rows[name] = lobo(data, config, model_id)
        pct = [r["pct_error"] for r in rows[name].values()]
        cov = np.mean([r["covered"] for r in rows[name].values()])
        print(f"{name}: {len(common)} buildings, model {model_id}, leave-one-out ε_t median "
              f"error {np.nanmedian(pct):.0%}, 90 % interval coverage {cov:.0%}")
    counted = right = 0
    print("| building | ε_t GMapping measured / predicted | ε_t Karto measured / predicted | "
          "call (P) | measured better | counted |")
    print("|---|---|---|---|---|---|")
    for world in common:
        g, k = rows["gmapping"][world], rows["karto"][world]
        call = decide("gmapping", "karto", {"gmapping": entry(g), "karto": entry(k)},
                      {"gmapping": config.conformal.confidence,
                       "karto": config.conformal.confidence})
        better = "gmapping" if g["y"] < k["y"] else "karto"
        differ = abs(g["y"] - k["y"]) / min(g["y"], k["y"]) > args.min_difference
        p = call["probability"][call["verdict"]] if call["verdict"] in ("gmapping", "karto") \
            else max(call["probability"].values())
        counted += differ
        right += differ and call["verdict"] == better
        print(f"| {world} | {g['y']:.3f} / {g['prediction']:.3f} | {k['y']:.3f} / "
              f"{k['prediction']:.3f} | {call['verdict']} ({p:.2f}) | {better} | "
              f"{'yes' if differ else 'no'} |")
    share = right / counted if counted else float("nan")
    print(f"pairs whose measured ε_t differ by > {args.min_difference:.0%}: {counted}; "
          f"the call names the measured better algorithm in {right} ({share:.0%})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
