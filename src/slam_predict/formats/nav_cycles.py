"""Captured local-planner cycles for the real base_local_planner: the exact input of our
TrajectoryPlanner's ``find_best_path`` calls, for the differential check against
``base_local_planner::TrajectoryPlanner`` (``bench/nav_diff/driver.cpp`` reads it,
``bench/bench_nav_diff.py`` writes it from an in-process episode), and the driver's output.

A case is a folder with two input files. ``params.txt``: one ``key value`` line per
TrajectoryPlanner parameter (our config's names), ``sim_period`` (s) and
``footprint n x_0 y_0 ... x_n-1 y_n-1`` (m, the padded polygon the planner checks). Numbers are
written with ``repr`` so both sides see identical doubles.

``cycles.bin`` (little-endian): the magic ``SPNAVC01``, then records, each a one-byte tag:

- ``M`` a local costmap, valid for the cycles after it: uint32 size_x, size_y; float64
  resolution (m), origin x, origin y (m); uint32 n; n bytes of zlib-compressed uint8 costs,
  row-major (index my·size_x + mx, as costmap_2d);
- ``C`` a cycle: uint32 index; float64 t (s), robot x, y (m), θ (rad) in the costmap frame,
  odometry v (m/s), ω (rad/s), our command vx (m/s), vθ (rad/s); uint32 n; n plan poses
  (x, y, θ float64) as passed to ``updatePlan`` (transformed, cut and pruned);
- ``E`` the end.

The driver writes text: the line ``nav_diff_driver 1``, then per cycle ``index xv thetav cost
escaping stuck_left stuck_right rotating_left rotating_right ours_cost`` (its best sample, its
mode flags after the cycle, and its cost of our command; see :data:`DRIVER_COLUMNS`).
"""
from __future__ import annotations

import dataclasses
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from slam_predict.errors import InputError, require_file

MAGIC = b"SPNAVC01"
DRIVER_FORMAT = "nav_diff_driver 1"
DRIVER_COLUMNS = ("index", "xv", "thetav", "cost", "escaping", "stuck_left", "stuck_right",
                  "rotating_left", "rotating_right", "ours_cost")
COSTMAP_HEAD = struct.Struct("<IIdddI")   # size x, size y, resolution, origin x, y, n bytes
_CYCLE = struct.Struct("<IddddddddI")


@dataclass
class Cycle:
    """One captured cycle: pose (x m, y m, θ rad), velocity (v m/s, ω rad/s), plan (n, 3) and
    our command (vx m/s, vθ rad/s); ``costmap`` is the local costmap it was planned on."""

    index: int
    t: float
    pose: tuple[float, float, float]
    vel: tuple[float, float]
    plan: np.ndarray
    ours: tuple[float, float]
    costmap: LocalMap


@dataclass
class LocalMap:
    """A local costmap: costs uint8 [size_y, size_x], origin (m), resolution (m)."""

    costs: np.ndarray
    origin: tuple[float, float]
    resolution: float


def costmap_record(costmap) -> bytes:
    """A costmap (``costs`` uint8 [size_y, size_x], ``origin`` m, ``resolution`` m) as the
    captures store it: :data:`COSTMAP_HEAD`, then the zlib-compressed costs (read by
    bench/nav_diff/record_reader.h ``ReadCostmap``)."""
    costs = np.ascontiguousarray(costmap.costs, dtype=np.uint8)
    packed = zlib.compress(costs.tobytes(), 6)
    return COSTMAP_HEAD.pack(costs.shape[1], costs.shape[0], float(costmap.resolution),
                             float(costmap.origin[0]), float(costmap.origin[1]),
                             len(packed)) + packed


class CycleWriter:
    """Writes ``cycles.bin``: :meth:`cycle` adds a map record only when the costmap changed."""

    def __init__(self, path: Path):
        self._file = open(path, "wb")
        self._file.write(MAGIC)
        self._last: LocalMap | None = None
        self.maps = 0
        self.cycles = 0

    def _map(self, local: LocalMap) -> None:
        self._file.write(b"M" + costmap_record(local))
        self._last = LocalMap(np.array(local.costs, dtype=np.uint8), local.origin,
                              local.resolution)
        self.maps += 1

    def cycle(self, cycle: Cycle) -> None:
        """Append one cycle (and its costmap when it differs from the last one written)."""
        last, local = self._last, cycle.costmap
        if (last is None or last.origin != local.origin or last.resolution != local.resolution
                or not np.array_equal(last.costs, local.costs)):
            self._map(local)
        plan = np.ascontiguousarray(cycle.plan, dtype="<f8").reshape(-1, 3)
        self._file.write(b"C" + _CYCLE.pack(cycle.index, cycle.t, *cycle.pose, *cycle.vel,
                                            *cycle.ours, len(plan)))
        self._file.write(plan.tobytes())
        self.cycles += 1

    def close(self) -> None:
        self._file.write(b"E")
        self._file.close()


def read_cycles(path: Path):
    """Yield the :class:`Cycle` records of a ``cycles.bin`` file."""
    data = Path(require_file(path, "captured cycles")).read_bytes()
    if data[:8] != MAGIC:
        raise InputError(f"{path}: not a captured-cycles file ({MAGIC.decode()})")
    at, local = 8, None
    while at < len(data):
        tag, at = data[at:at + 1], at + 1
        if tag == b"E":
            return
        if tag == b"M":
            sx, sy, res, ox, oy, n = COSTMAP_HEAD.unpack_from(data, at)
            at += COSTMAP_HEAD.size
            costs = np.frombuffer(zlib.decompress(data[at:at + n]), np.uint8).reshape(sy, sx)
            local, at = LocalMap(costs, (ox, oy), res), at + n
        elif tag == b"C" and local is not None:
            k, t, x, y, th, v, w, ovx, ovth, n = _CYCLE.unpack_from(data, at)
            at += _CYCLE.size
            plan = np.frombuffer(data, "<f8", 3 * n, at).reshape(n, 3).copy()
            at += 24 * n
            yield Cycle(k, t, (x, y, th), (v, w), plan, (ovx, ovth), local)
        else:
            raise InputError(f"{path}: bad record at byte {at - 1}")
    raise InputError(f"{path}: truncated (no end record)")


def write_params(path: Path, cfg, footprint: np.ndarray, sim_period: float) -> None:
    """``params.txt`` of a case: the dataclass ``cfg``'s scalar fields, sim_period (s) and the
    footprint (k, 2) (m)."""
    lines = []
    for f in dataclasses.fields(cfg):
        value = getattr(cfg, f.name)
        if isinstance(value, bool):
            lines.append(f"{f.name} {int(value)}")
        elif isinstance(value, (int, float)):
            lines.append(f"{f.name} {float(value)!r}")
    lines.append(f"sim_period {float(sim_period)!r}")
    fp = np.asarray(footprint, dtype=float).reshape(-1, 2)
    lines.append("footprint " + " ".join([str(len(fp))] + [repr(float(v)) for v in fp.ravel()]))
    Path(path).write_text("\n".join(lines) + "\n")


def read_driver_output(path: Path) -> dict[str, np.ndarray]:
    """The driver's output as columns (:data:`DRIVER_COLUMNS`), one row per cycle."""
    lines = Path(require_file(path, "driver output")).read_text().splitlines()
    if not lines or lines[0].strip() != DRIVER_FORMAT:
        raise InputError(f"{path}: not a {DRIVER_FORMAT!r} file")
    rows = np.array([[float(v) for v in line.split()] for line in lines[1:] if line.strip()])
    rows = rows.reshape(-1, len(DRIVER_COLUMNS))
    return {name: rows[:, k] for k, name in enumerate(DRIVER_COLUMNS)}
