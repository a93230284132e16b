"""Batches of runs: worlds × runs, resumable, on local processes or a Dask cluster.

Each run is an independent task ``episode_fn(RunSpec) -> dict`` that writes its own record
folder atomically and returns its run.json content. Finished runs are never redone; a run that
was interrupted left only a temporary folder, which is deleted and the run redone from scratch.
With ``runs='auto'`` the number of runs per world follows the thesis: a pilot of 10 runs, then
|R| = ⌈z²·s²/d²⌉ re-estimated after each round until it is ≤ the runs done (``max_runs`` caps it).

Runs are started lazily, at most ``jobs`` at a time, and counted as each finishes. SIGINT/SIGTERM
set a stop flag (:mod:`slam_predict.collect.interrupt`) that the episode loop checks every control
step: no new run starts, the runs in progress end at their next step and are discarded, local
workers get the signal forwarded and are waited for (at most ``STOP_WAIT_S``, then killed).
"""
from __future__ import annotations

import concurrent.futures as futures
import contextlib
import dataclasses
import importlib
import logging
import os
import signal
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from tqdm import tqdm

from slam_predict.collect import interrupt
from slam_predict.collect.store import RunStore, run_seed
from slam_predict.words import plural

LOG = logging.getLogger(__name__)
STOP_WAIT_S = 30.0  # wall time the runs in progress get to stop after a signal


@dataclass(frozen=True)
class RunSpec:
    """One run to do: the world file, its name, the run index, its seed and where to write."""

    world_path: str
    world: str
    index: int
    seed: int
    out_dir: str
    options: dict = field(default_factory=dict, hash=False, compare=False)


@dataclass
class BatchConfig:
    """Batch settings: runs per world (int or 'auto'), caps, parallelism, base seed."""

    runs: int | str = 5
    pilot_runs: int = 10
    max_runs: int = 50
    jobs: int = 1
    scheduler: str | None = None
    base_seed: int = 0
    progress: bool = True
    episode: str = "slam_predict.collect.episode:run_episode"
    options: dict = field(default_factory=dict)


def resolve_callable(path: str) -> Callable:
    """Import ``'package.module:function'``."""
    module, _, name = path.partition(":")
    return getattr(importlib.import_module(module), name)


def _call_episode(episode: str, spec: RunSpec) -> dict:
    """Top-level (picklable) task body: run one episode; a stop request ends it early."""
    with interrupt.running():
        try:
            interrupt.check()
            return resolve_callable(episode)(spec)
        except interrupt.Interrupted:
            if interrupt.parent_died():  # a worker whose batch is gone: nobody to report to
                os._exit(128 + signal.SIGTERM)
            raise


Outcome = tuple[RunSpec, dict | None, BaseException | None]


class _Executor:
    """Runs episodes lazily, at most ``jobs`` at a time, and yields each as it finishes: in the
    current process (``jobs`` 1), in local worker processes, or on a Dask cluster."""

    def __init__(self, jobs: int, scheduler: str | None):
        self.client = None
        self.pool = None
        self.slots = max(1, int(jobs))
        self.signalled: set[int] = set()   # local workers a stop signal was passed on to
        if scheduler:
            from dask.distributed import Client
            self.client = scheduler if not isinstance(scheduler, str) else Client(scheduler)
        elif jobs > 1:
            self.pool = futures.ProcessPoolExecutor(
                max_workers=jobs, initializer=interrupt.init_worker, initargs=(os.getpid(),))

    @property
    def in_process(self) -> bool:
        """Episodes run in this process (one at a time), where they can draw a progress bar."""
        return self.pool is None and self.client is None

    def forward_signal(self, signum: int) -> None:
        """Pass a stop signal on to the local worker processes."""
        for pid in self._worker_pids():
            self._kill(pid, signum)

    def forward_to_late_workers(self, signum: int) -> None:
        """Pass a stop signal on to the workers started after it was forwarded (the pool
        starts them as runs are submitted, so one may start while the signal is handled)."""
        for pid in self._worker_pids():
            if pid not in self.signalled:
                self._kill(pid, signum)

    def _kill(self, pid: int, signum: int) -> None:
        self.signalled.add(pid)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(pid, signum)

    def _worker_pids(self) -> list[int]:
        processes = getattr(self.pool, "_processes", None) or {}
        return [int(pid) for pid in list(processes)]

    def outcomes(self, episode: str, specs: Sequence[RunSpec]) -> Iterator[Outcome]:
        """(spec, run.json, None) or (spec, None, error) per run, in the order they finish;
        no new run starts once a stop was requested."""
        if self.in_process:
            yield from self._in_process(episode, specs)
        else:
            yield from self._parallel(episode, specs)

    @staticmethod
    def _in_process(episode: str, specs: Sequence[RunSpec]) -> Iterator[Outcome]:
        for spec in specs:
            if interrupt.stop_signal() is not None:
                return
            try:
                yield spec, _call_episode(episode, spec), None
            except Exception as exc:  # noqa: BLE001 - reported per run
                yield spec, None, exc

    def _submit(self, episode: str, spec: RunSpec):
        if self.client is not None:
            return self.client.submit(_call_episode, episode, spec, pure=False)
        return self.pool.submit(_call_episode, episode, spec)

    def _parallel(self, episode: str, specs: Sequence[RunSpec]) -> Iterator[Outcome]:
        queue = iter(specs)
        slots = self.slots if self.pool is not None else len(specs)
        running: dict = {}
        stop_deadline = None
        while True:
            while len(running) < slots and interrupt.stop_signal() is None:
                spec = next(queue, None)
                if spec is None:
                    break
                running[self._submit(episode, spec)] = spec
            if not running:
                return
            if interrupt.stop_signal() is not None:
                self.forward_to_late_workers(interrupt.stop_signal())
                stop_deadline = stop_deadline or time.monotonic() + STOP_WAIT_S
                if time.monotonic() > stop_deadline:
                    self._abandon(running)
                    return
            for job in self._wait_some(list(running)):
                spec = running.pop(job)
                try:
                    yield spec, job.result(), None
                except Exception as exc:  # noqa: BLE001 - reported per run
                    yield spec, None, exc

    def _wait_some(self, jobs: list, timeout: float = 0.5) -> list:
        """The jobs that finished within ``timeout`` s (at least one, unless it expired)."""
        if self.client is not None:
            from dask.distributed import wait
            with contextlib.suppress(TimeoutError, futures.TimeoutError):
                wait(jobs, timeout=timeout, return_when="FIRST_COMPLETED")
            return [job for job in jobs if job.done()]
        done, _ = futures.wait(jobs, timeout=timeout, return_when=futures.FIRST_COMPLETED)
        return list(done)

    def _abandon(self, running: dict) -> None:
        """Give up on runs that did not stop within ``STOP_WAIT_S``: kill local workers."""
        LOG.warning("%s did not stop within %.0f s: killing them", plural(len(running), "run"),
                    STOP_WAIT_S)
        if self.client is not None:
            self.client.cancel(list(running))
            return
        self.forward_signal(signal.SIGKILL)

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=True)
        if self.client is not None and hasattr(self.client, "close") and not getattr(
                self, "_shared_client", False):
            self.client.close()


class Batch:
    """Run (or resume) a campaign over ``worlds`` (name → world file path)."""

    def __init__(self, worlds: dict[str, str], out: str | Path, config: BatchConfig,
                 runs_needed: Callable[[list[dict], int], int] | None = None):
        self.worlds = dict(worlds)
        self.store = RunStore(Path(out))
        self.config = config
        self.runs_needed = runs_needed or _thesis_runs_needed
        self.failures: list[str] = []
        self.stopped_by: int | None = None

    def target(self, world: str) -> int:
        """How many runs ``world`` needs now (fixed, or estimated from its records)."""
        if self.config.runs != "auto":
            return int(self.config.runs)
        records = self.store.records(world)
        if len(records) < self.config.pilot_runs:
            return self.config.pilot_runs
        return min(self.config.max_runs, max(len(records), self.runs_needed(records, len(records))))

    def pending(self) -> list[RunSpec]:
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
        """Do every pending run (repeating rounds for 'auto'); returns the number of runs done.

        SIGINT/SIGTERM stop the batch within one control step: finished runs are kept, the runs
        in progress are discarded (their temporary folders removed) and :attr:`stopped_by` is
        set to the signal number. Another batch already writing to the same folder is an
        :class:`~slam_predict.errors.InputError` (its runs in progress would look like leftovers).
        """
        with self.store.lock():
            return self._run_locked()

    def _run_locked(self) -> int:
        removed = self.store.remove_leftovers()
        if removed:
            LOG.info("removed %s", plural(removed, "interrupted run folder"))
        interrupt.reset()
        executor = _Executor(self.config.jobs, self.config.scheduler)
        total = 0
        try:
            with interrupt.signal_handlers(forward=executor.forward_signal):
                while interrupt.stop_signal() is None:
                    specs = self.pending()
                    if not specs:
                        break
                    total += self._round(executor, specs)
                    if self.config.runs != "auto" or self.failures:
                        break
        finally:
            executor.close()
            self.stopped_by = interrupt.stop_signal()
            if self.stopped_by is not None:
                self.store.remove_leftovers()
        return total

    def _round(self, executor: _Executor, specs: Sequence[RunSpec]) -> int:
        started = time.perf_counter()
        if self.config.progress and executor.in_process:   # each run shows its sim time too
            specs = [dataclasses.replace(s, options={**s.options, "progress": True})
                     for s in specs]
        bar = tqdm(total=len(specs), unit="run", disable=not self.config.progress,
                   desc="collect")
        done = 0
        for spec, _record, error in executor.outcomes(self.config.episode, specs):
            if isinstance(error, interrupt.Interrupted):
                LOG.info("%s run %d stopped before its end: discarded", spec.world, spec.index)
                continue
            if error is not None:  # one failed run must not stop the batch
                LOG.error("%s run %d failed: %s", spec.world, spec.index, error)
                self.failures.append(f"{spec.world}/{spec.index}: {error}")
            else:
                done += 1
            bar.update(1)
        bar.close()
        LOG.info("%s in %.1f s", plural(done, "run"), time.perf_counter() - started)
        return done


def _thesis_runs_needed(records: list[dict], done: int) -> int:
    """Total runs the world needs by the thesis' rule (:func:`metric.sampling.run_count`)."""
    from slam_predict.collect.record import with_metric
    from slam_predict.metric.sampling import run_count

    records = with_metric(records)
    return run_count([r["metric"]["trans_mean"] for r in records],
                     [r["metric"]["rot_mean"] for r in records]).runs_required
