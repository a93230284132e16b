"""When the closed loop publishes the SLAM map: slam_toolbox's map thread republishes every
map_update_interval s whether or not a scan was processed; slam_gmapping only with a processed
scan. Checked on a robot standing still (Karto processes its first scan only)."""
from __future__ import annotations

import numpy as np
import pytest

from slam_predict.explore import run as runner
from slam_predict.explore.loop import ClosedLoop
from slam_predict.world.load import load_plan

SIM_S = 21.0   # s standing still


def still_loop(root, map_source: str) -> tuple[ClosedLoop, list]:
    """A loop of tiny.world whose explorer sends no goal; returns it and its publications
    (sim s, grid) as the navigator receives them."""
    settings = runner.load_explore_settings(root / "config")
    world = load_plan(root / "worlds" / "tiny.world")
    loop = ClosedLoop(world, 3, settings.nav, settings.explore, settings.sim,
                      map_source=map_source)
    loop.explorer.step = lambda t, grid, pose: None
    published = []
    set_map = loop.navigator.set_map

    def recording(grid):
        published.append((loop.t, grid))
        set_map(grid)

    loop.navigator.set_map = recording
    while loop.t < SIM_S:
        loop.step()
    return loop, published


def test_karto_map_is_republished_every_interval_without_new_scans(root):
    loop, published = still_loop(root, "karto")
    assert loop.source.stats()["scans_processed"] == 1
    interval = loop.map_update_interval
    times = np.array([t for t, _ in published])
    # the first map with the first scan, then one per interval (at the next scan, 0.1 s)
    assert len(times) == 1 + int(SIM_S // interval)
    assert np.all(np.abs(np.diff(times) - interval) <= 0.1 + 1e-9)
    grids = [g for _, g in published]
    assert len({id(g) for g in grids}) == len(grids)     # every publication a new message
    assert all(np.array_equal(g.data, grids[0].data) for g in grids)


def test_without_a_map_thread_only_processed_scans_publish(root):
    loop, published = _without_thread(root)
    assert loop.source.stats()["scans_processed"] == 1
    assert len(published) == 1


def _without_thread(root):
    """The same run with the map thread switched off (slam_gmapping's rule)."""
    original = ClosedLoop.__init__

    def init(self, *args, **kwargs):
        original(self, *args, **kwargs)
        self._map_thread = False

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(ClosedLoop, "__init__", init)
        return still_loop(root, "karto")


def test_gmapping_has_no_map_thread():
    from slam_predict import slam

    assert slam.backend_class("karto").map_thread
    assert not slam.backend_class("gmapping").map_thread
