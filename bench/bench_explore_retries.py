"""Exploration with GMapping in the loop with and without the explorer's ``blacklist_retries``.

    source setup.bash
    python bench/bench_explore_retries.py [--runs Borchen4_updated:1 Sabadell3_updated:2]
        [--worlds-dir out/thesis_worlds] [--settings config/collect.yaml] [--retries 0 3]

Each ``WORLD:INDEX`` is the campaign run of that index (seed ``run_seed(base_seed 0, world,
index)``, as ``slam-predict collect`` derives it), explored in-process until the explorer stops
or ``--max-sim-time``. Prints per run and retry setting: the explorer's stop reason and sim
time, the goal outcomes, the coverage of the reachable free area, the wall time. The defaults
are the two realistic-campaign runs that stopped early with ``all_frontiers_blacklisted``
(``slam-predict worlds import-thesis`` builds the worlds).
"""
from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def explore(world_path: Path, world_name: str, index: int, settings, max_sim_time: float) -> dict:
    """Run one closed loop until the explorer stops; its summary."""
    from slam_predict.collect.store import run_seed
    from slam_predict.explore.coverage import coverage, reachable_free
    from slam_predict.explore.loop import ClosedLoop
    from slam_predict.nav.costmap import inscribed_radius
    from slam_predict.world.load import load_plan

    world = load_plan(world_path)
    seed = run_seed(0, world_name, index)
    loop = ClosedLoop(world, seed, settings.nav, settings.explore, settings.sim,
                      map_source="gmapping", slam_params=settings.slam.params)
    start = time.perf_counter()
    reason = loop.run(max_sim_time)
    reach = reachable_free(world, inscribed_radius(settings.nav.global_costmap))
    return {"seed": seed, "reason": reason, "t": loop.t, "wall": time.perf_counter() - start,
            "goals": loop.explorer.log.counts(),
            "coverage": coverage(world, loop.source.map(), reach, loop.world_T_map)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", nargs="+", default=["Borchen4_updated:1", "Sabadell3_updated:2"])
    parser.add_argument("--worlds-dir", type=Path, default=ROOT / "out" / "thesis_worlds")
    parser.add_argument("--settings", type=Path, default=ROOT / "config" / "collect.yaml")
    parser.add_argument("--retries", type=int, nargs="+", default=[0, 3])
    parser.add_argument("--max-sim-time", type=float, default=3600.0)
    args = parser.parse_args()

    from slam_predict.collect.settings import load_settings

    settings = load_settings(args.settings)
    for item in args.runs:
        name, _, index = item.partition(":")
        for retries in args.retries:
            settings.explore = dataclasses.replace(settings.explore, blacklist_retries=retries)
            out = explore(args.worlds_dir / f"{name}.world", name, int(index or 0), settings,
                          args.max_sim_time)
            print(f"{name} run {index} (seed {out['seed']}) blacklist_retries={retries}: "
                  f"{out['reason']} at {out['t']:.1f} s sim, coverage {out['coverage']:.3f}, "
                  f"goals {out['goals']}, {out['wall']:.0f} s wall", flush=True)


if __name__ == "__main__":
    main()
