"""Batches of runs: worlds × runs, resumable, on local processes or a Dask cluster.

Each run is an independent task ``episode_fn(RunSpec) -> dict`` that writes its own record
folder atomically and returns its run.json content. Finished runs are never redone; a run that
was interrupted left only a temporary folder, which is deleted and the run redone from scratch.
With ``runs='auto'`` the number of runs per world follows the thesis: a pilot of 10 runs, then
|R| = ⌈z²·s²/d²⌉ re-estimated after each round until it is ≤ the runs done (``max_runs`` caps it).
"""
from __future__ import annotations

import concurrent.futures as futures
import importlib
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence, Union

from tqdm import tqdm

from slam_predict.collect.store import RunStore, run_seed

LOG = logging.getLogger(__name__)


@dataclass(frozen=True)
class RunSpec:
    """One run to do: the world file, its name, the run index, its seed and where to write."""

    world_path: str
    world: str
    index: int
    seed: int
    out_dir: str
    options: Dict = field(default_factory=dict, hash=False, compare=False)


@dataclass
class BatchConfig:
    """Batch settings: runs per world (int or 'auto'), caps, parallelism, base seed."""

    runs: Union[int, str] = 5
    pilot_runs: int = 10
    max_runs: int = 50
    jobs: int = 1
    scheduler: Optional[str] = None
    base_seed: int = 0
    progress: bool = True
    episode: str = "slam_predict.collect.episode:run_episode"
    options: Dict = field(default_factory=dict)


def resolve_callable(path: str) -> Callable:
    """Import ``'package.module:function'``."""
    module, _, name = path.partition(":")
    return getattr(importlib.import_module(module), name)


def _call_episode(episode: str, spec: RunSpec) -> dict:
    """Top-level (picklable) task body: run one episode."""
    return resolve_callable(episode)(spec)


class _Executor:
    """Submit/collect over a local process pool, the current process, or Dask distributed."""

    def __init__(self, jobs: int, scheduler: Optional[str]):
        self.client = None
        self.pool = None
        if scheduler:
            from dask.distributed import Client
            self.client = scheduler if not isinstance(scheduler, str) else Client(scheduler)
        elif jobs > 1:
            self.pool = futures.ProcessPoolExecutor(max_workers=jobs)

    def submit(self, episode: str, spec: RunSpec):
        if self.client is not None:
            return self.client.submit(_call_episode, episode, spec, pure=False)
        if self.pool is not None:
            return self.pool.submit(_call_episode, episode, spec)
        done = futures.Future()
        try:
            done.set_result(_call_episode(episode, spec))
        except BaseException as exc:  # noqa: BLE001 - reported through the future
            done.set_exception(exc)
        return done

    def as_completed(self, items: List):
        if self.client is not None:
            from dask.distributed import as_completed
            return as_completed(items)
        return futures.as_completed(items)

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown()
        if self.client is not None and hasattr(self.client, "close") and not getattr(
                self, "_shared_client", False):
            self.client.close()


class Batch:
    """Run (or resume) a campaign over ``worlds`` (name → world file path)."""

    def __init__(self, worlds: Dict[str, str], out: Union[str, Path], config: BatchConfig,
                 runs_needed: Optional[Callable[[List[dict], int], int]] = None):
        self.worlds = dict(worlds)
        self.store = RunStore(Path(out))
        self.config = config
        self.runs_needed = runs_needed or _default_runs_needed(config)
        self.failures: List[str] = []

    def target(self, world: str) -> int:
        """How many runs ``world`` needs now (fixed, or estimated from its records)."""
        if self.config.runs != "auto":
            return int(self.config.runs)
        records = self.store.records(world)
        if len(records) < self.config.pilot_runs:
            return self.config.pilot_runs
        return min(self.config.max_runs, max(len(records), self.runs_needed(records, len(records))))

    def pending(self) -> List[RunSpec]:
        """Runs still to do, index-major (every world's run 0, then every world's run 1, …), so
        an interrupted campaign has its runs spread over all worlds."""
        specs = []
        for world, path in self.worlds.items():
            done = set(self.store.completed(world))
            for index in range(self.target(world)):
                if index not in done:
                    specs.append(RunSpec(str(path), world, index,
                                         run_seed(self.config.base_seed, world, index),
                                         str(self.store.run_dir(world, index)),
                                         dict(self.config.options)))
        return sorted(specs, key=lambda spec: spec.index)

    def run(self) -> int:
        """Do every pending run (repeating rounds for 'auto'); returns the number of runs done."""
        removed = self.store.remove_leftovers()
        if removed:
            LOG.info("removed %d interrupted run folders", removed)
        executor = _Executor(self.config.jobs, self.config.scheduler)
        total = 0
        try:
            while True:
                specs = self.pending()
                if not specs:
                    return total
                total += self._round(executor, specs)
                if self.config.runs != "auto" or self.failures:
                    return total
        finally:
            executor.close()

    def _round(self, executor: _Executor, specs: Sequence[RunSpec]) -> int:
        started = time.perf_counter()
        jobs = {executor.submit(self.config.episode, spec): spec for spec in specs}
        bar = tqdm(total=len(jobs), unit="run", disable=not self.config.progress,
                   desc="collect")
        done = 0
        for job in executor.as_completed(list(jobs)):
            spec = jobs[job]
            try:
                job.result()
                done += 1
            except Exception as exc:  # noqa: BLE001 - one failed run must not stop the batch
                LOG.error("%s run %d failed: %s", spec.world, spec.index, exc)
                self.failures.append(f"{spec.world}/{spec.index}: {exc}")
            bar.update(1)
        bar.close()
        LOG.info("%d runs in %.1f s", done, time.perf_counter() - started)
        return done


def _default_runs_needed(config: BatchConfig) -> Callable[[List[dict], int], int]:
    def needed(records: List[dict], done: int) -> int:
        from slam_predict.metric.stats import required_runs
        return required_runs([r["metric"]["trans_mean"] for r in records],
                             [r["metric"]["rot_mean"] for r in records])
    return needed
