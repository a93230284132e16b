"""The on-disk campaign store: ``DATA/<world>/<run-id>/`` folders, each written atomically.

A run folder exists only once its run is complete (the episode writes a temporary folder and
renames it), so resuming a batch means: list complete runs, delete leftovers of interrupted runs
(hidden ``.run_*.tmp`` folders), and schedule the missing run indices.
"""
from __future__ import annotations

import contextlib
import fcntl
import json
import logging
import os
import shutil
import zlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from slam_predict.errors import InputError

LOG = logging.getLogger(__name__)
RUN_JSON = "run.json"
LOCK_FILE = ".collect.lock"


def run_id(index: int) -> str:
    """Folder name of run ``index``."""
    return f"run_{index:03d}"


def run_seed(base_seed: int, world: str, index: int) -> int:
    """Deterministic 32-bit seed of one run from the batch seed, the world name and the index."""
    sequence = np.random.SeedSequence([base_seed, zlib.crc32(world.encode()), index])
    return int(sequence.generate_state(1)[0])


@dataclass
class RunStore:
    """Run records below ``root`` (one folder per world, one sub-folder per run)."""

    root: Path

    def __post_init__(self) -> None:
        self.root = Path(self.root)

    def run_dir(self, world: str, index: int) -> Path:
        """Final folder of a run."""
        return self.root / world / run_id(index)

    def completed(self, world: str) -> list[int]:
        """Indices of complete runs of ``world`` (folders holding a readable run.json)."""
        indices = []
        for path in sorted((self.root / world).glob("run_[0-9][0-9][0-9]")):
            try:
                json.loads((path / RUN_JSON).read_text())
            except (OSError, ValueError):
                LOG.warning("%s: incomplete run folder ignored", path)
                continue
            indices.append(int(path.name.split("_")[1]))
        return indices

    @contextlib.contextmanager
    def lock(self) -> Iterator[None]:
        """Hold the store for one batch: a second batch on the same folder (which would delete
        this one's runs in progress as leftovers) gets an :class:`InputError` instead. The lock
        is the kernel's (``flock``), so a killed batch never leaves the folder locked."""
        self.root.mkdir(parents=True, exist_ok=True)
        path = self.root / LOCK_FILE
        with open(path, "a+", encoding="utf-8") as handle:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                handle.seek(0)
                holder = handle.read().strip() or "unknown"
                raise InputError(f"another collect (pid {holder}) is writing to this campaign "
                                 "folder; wait for it, or run in parallel with --jobs",
                                 self.root) from None
            handle.seek(0)
            handle.truncate()
            handle.write(f"{os.getpid()}\n")
            handle.flush()
            try:
                yield
            finally:
                fcntl.flock(handle, fcntl.LOCK_UN)

    def remove_leftovers(self) -> int:
        """Delete temporary folders of interrupted runs (and world folders left empty); returns
        how many runs were removed."""
        removed = 0
        for path in self.root.glob("*/.run_*.tmp"):
            shutil.rmtree(path, ignore_errors=True)
            removed += 1
        for world in self.root.iterdir() if self.root.is_dir() else []:
            if world.is_dir() and not any(world.iterdir()):
                world.rmdir()  # its only run was interrupted
        return removed

    def records(self, world: str) -> list[dict]:
        """The run.json contents of every complete run of ``world``, by index."""
        return [json.loads((self.run_dir(world, i) / RUN_JSON).read_text())
                for i in self.completed(world)]

    def worlds(self) -> list[str]:
        """Worlds that have at least one complete run."""
        return sorted(p.name for p in self.root.iterdir()
                      if p.is_dir() and not p.name.startswith(".") and self.completed(p.name))
