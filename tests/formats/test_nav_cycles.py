"""Captured local-planner cycles (the differential check's input for the real
base_local_planner), the case parameters and the driver's output."""
import numpy as np
import pytest

from slam_predict.errors import InputError
from slam_predict.formats.nav_cycles import (
    DRIVER_COLUMNS,
    DRIVER_FORMAT,
    Cycle,
    CycleWriter,
    LocalMap,
    read_cycles,
    read_driver_output,
    write_params,
)
from slam_predict.nav.config import TrajectoryPlannerConfig


def _cycle(rng, k, local):
    return Cycle(k, 0.1 * k + 1 / 3, tuple(rng.normal(0, 3, 3)), tuple(rng.normal(0, 1, 2)),
                 rng.normal(0, 2, (k + 1, 3)), tuple(rng.normal(0, 1, 2)), local)


def test_cycles_read_back_exactly_with_maps_only_when_changed(tmp_path):
    rng = np.random.default_rng(3)
    first = LocalMap(rng.integers(0, 256, (5, 7), dtype=np.uint8), (-1.25, 2.0 / 3), 0.02)
    moved = LocalMap(first.costs.copy(), (-1.23, 2.0 / 3), 0.02)
    changed = LocalMap(first.costs.copy(), moved.origin, 0.02)
    changed.costs[4, 6] ^= 1
    cycles = [_cycle(rng, k, local)
              for k, local in enumerate([first, first, moved, moved, changed])]
    writer = CycleWriter(tmp_path / "cycles.bin")
    for cycle in cycles:
        writer.cycle(cycle)
    writer.close()
    assert (writer.cycles, writer.maps) == (5, 3)
    back = list(read_cycles(tmp_path / "cycles.bin"))
    assert len(back) == 5
    for a, b in zip(cycles, back, strict=True):
        assert (a.index, a.t, a.pose, a.vel, a.ours) == (b.index, b.t, b.pose, b.vel, b.ours)
        assert np.array_equal(a.plan, b.plan)
        assert np.array_equal(a.costmap.costs, b.costmap.costs)
        assert (a.costmap.origin, a.costmap.resolution) == (b.costmap.origin,
                                                            b.costmap.resolution)


def test_truncated_or_foreign_files_are_refused(tmp_path):
    path = tmp_path / "cycles.bin"
    writer = CycleWriter(path)
    writer.cycle(_cycle(np.random.default_rng(0), 0, LocalMap(np.zeros((2, 2), np.uint8),
                                                              (0.0, 0.0), 0.05)))
    writer.close()
    path.write_bytes(path.read_bytes()[:-1])
    with pytest.raises(InputError, match="truncated"):
        list(read_cycles(path))
    path.write_bytes(b"something else")
    with pytest.raises(InputError, match="not a captured-cycles file"):
        list(read_cycles(path))


def test_params_hold_every_scalar_the_footprint_and_the_period(tmp_path):
    cfg = TrajectoryPlannerConfig(occdist_scale=0.05, escape_alternate=True)
    footprint = np.array([[-0.21, -0.21], [-0.21, 0.21], [0.21, 0.21], [0.21, -0.21]])
    write_params(tmp_path / "params.txt", cfg, footprint, 0.1)
    lines = dict(line.split(" ", 1) for line in (tmp_path / "params.txt").read_text().splitlines())
    assert float(lines["occdist_scale"]) == 0.05 and lines["escape_alternate"] == "1"
    assert float(lines["sim_period"]) == 0.1 and "y_vels" not in lines
    values = lines["footprint"].split()
    assert int(values[0]) == 4 and np.array_equal(np.array(values[1:], float), footprint.ravel())


def test_driver_output_columns(tmp_path):
    path = tmp_path / "real.txt"
    path.write_text(f"{DRIVER_FORMAT}\n0 0.5 -0.25 12.5 0 0 1 0 1 13\n1 -0.15 0 1 1 0 1 0 1 -1\n")
    out = read_driver_output(path)
    assert list(out) == list(DRIVER_COLUMNS)
    assert out["xv"].tolist() == [0.5, -0.15] and out["escaping"].tolist() == [0, 1]
    path.write_text("something else\n")
    with pytest.raises(InputError):
        read_driver_output(path)
