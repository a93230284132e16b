"""The robot-configuration design: Latin hypercube strata, maximin choice, the dealing of
configurations over worlds, the robots it makes, and its file round trip and bad files."""
from __future__ import annotations

import itertools
import math
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from slam_predict.collect import robot_design as rd
from slam_predict.errors import InputError
from slam_predict.robot_file import DEG, load_robot

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "config" / "robots" / "seed_realistic.yaml"
WORLDS = [f"w{i:02d}" for i in range(21)]


@pytest.mark.parametrize("n, dims", [(1, 4), (7, 2), (28, 4)])
def test_every_column_has_one_point_per_stratum(n, dims):
    points = rd.latin_hypercube(n, dims, np.random.default_rng(3))
    assert points.shape == (n, dims) and points.min() >= 0 and points.max() < 1
    for column in points.T:
        assert sorted(np.floor(column * n).astype(int)) == list(range(n))


def test_maximin_keeps_the_best_candidate():
    """The kept design's smallest distance is the largest of the candidates drawn with the same
    generator state (brute force over the same candidates)."""
    chosen = rd.maximin_hypercube(10, 3, np.random.default_rng(5), candidates=30)
    rng = np.random.default_rng(5)
    candidates = [rd.latin_hypercube(10, 3, rng) for _ in range(30)]
    best = max(candidates, key=_brute_min_distance)
    np.testing.assert_array_equal(chosen, best)
    assert rd.min_distance(chosen) == pytest.approx(_brute_min_distance(best))


def _brute_min_distance(points):
    return min(math.dist(a, b) for a, b in itertools.combinations(points, 2))


def test_deal_gives_distinct_configs_and_balanced_use():
    configs = [f"c{k:02d}" for k in range(28)]
    dealt = rd.deal(WORLDS, configs, 4, np.random.default_rng(0))
    assert list(dealt) == WORLDS
    assert all(len(set(cs)) == 4 for cs in dealt.values())
    uses = Counter(c for cs in dealt.values() for c in cs)
    assert set(uses) == set(configs) and set(uses.values()) == {3}   # 21 x 4 = 28 x 3
    sets = [frozenset(cs) for cs in dealt.values()]
    assert len(set(sets)) == len(sets)          # no two worlds explored with the same robots
    pairs = Counter(p for cs in dealt.values() for p in itertools.combinations(sorted(cs), 2))
    assert max(pairs.values()) <= 2             # pairs of robots spread over the buildings


@pytest.mark.parametrize("n_worlds, n_configs, per_world", [(5, 7, 3), (9, 4, 4), (13, 28, 5)])
def test_deal_use_counts_differ_by_at_most_one(n_worlds, n_configs, per_world):
    configs = [f"c{k}" for k in range(n_configs)]
    dealt = rd.deal([f"w{i}" for i in range(n_worlds)], configs, per_world,
                    np.random.default_rng(n_worlds))
    uses = Counter(c for cs in dealt.values() for c in cs)
    counts = [uses.get(c, 0) for c in configs]
    assert max(counts) - min(counts) <= 1 and sum(counts) == n_worlds * per_world
    assert all(len(set(cs)) == per_world for cs in dealt.values())


def test_deal_refuses_more_points_than_configs():
    with pytest.raises(ValueError):
        rd.deal(WORLDS, ["c0", "c1"], 3, np.random.default_rng(0))


def test_design_is_seeded_and_spans_the_bounds():
    base = load_robot(BASE)
    one = rd.make_design(WORLDS, base, 28, 4, 2, seed=7)
    two = rd.make_design(WORLDS, base, 28, 4, 2, seed=7)
    other = rd.make_design(WORLDS, base, 28, 4, 2, seed=8)
    assert rd.design_dict(one) == rd.design_dict(two) != rd.design_dict(other)
    for factor, (low, high) in rd.DEFAULT_BOUNDS.items():
        values = np.array(sorted(c[factor] for c in one.configs.values()))
        if factor in rd.LOG_FACTORS:
            values, low, high = np.log(values), math.log(low), math.log(high)
        strata = np.floor((values - low) / (high - low) * 28 - 1e-6).astype(int)
        assert values[0] >= low and values[-1] <= high
        assert len(set(strata)) >= 27      # one per stratum (rounding may blur one edge)


def test_run_points_are_index_major_over_replicates():
    design = rd.make_design(WORLDS[:3], load_robot(BASE), 6, 2, 3, seed=0)
    points = [design.run_point("w01", i) for i in range(design.runs_per_world)]
    assert [p["replicate"] for p in points] == [0, 0, 1, 1, 2, 2]
    assert [p["config"] for p in points] == design.worlds["w01"] * 3
    assert points[0]["point"] == f"w01/{points[0]['config']}"
    with pytest.raises(KeyError):
        design.run_point("w01", 6)
    with pytest.raises(KeyError):
        design.run_point("nowhere", 0)


def test_configured_robot_scales_the_base():
    base = load_robot(BASE)
    robot = rd.configured_robot(base, {"range_max": 5.6, "fov": 240.0, "odom_xy_scale": 0.5,
                                       "odom_yaw_scale": 2.0}, 0.5, "c03")
    assert robot.laser.range_max == 5.6 and robot.laser.fov == 240.0
    assert robot.laser.samples == 481 and robot.laser.rate_hz == base.laser.rate_hz
    assert robot.odom_error == pytest.approx((0.005, 0.005, 4.0))
    sensor = robot.to_sensor_config()
    assert sensor.odom.error[2] == pytest.approx(4.0 * DEG)
    assert robot.footprint_side == base.footprint_side and robot.name.endswith("c03")


def test_file_round_trip(tmp_path):
    design = rd.make_design(WORLDS[:5], load_robot(BASE), 5, 2, 2, seed=1)
    path = tmp_path / "design.yaml"
    rd.write_design(design, path)
    again = rd.load_design(path)
    assert rd.design_dict(again) == rd.design_dict(design)
    assert again.robot("c02") == design.robot("c02")


@pytest.mark.parametrize("edit, message", [
    (lambda d: d.update(kind="plan"), "not a robot design"),
    (lambda d: d["worlds"]["w00"].__setitem__(0, "c99"), "unknown or repeated"),
    (lambda d: d["worlds"]["w01"].pop(), "same, non-zero number"),
    (lambda d: d["configs"]["c00"].pop("fov"), "bad design"),
    (lambda d: d["configs"]["c00"].update(range_max=-1.0), "range_max"),
    (lambda d: d["base_robot"].update(wheels=4), "unknown config key 'wheels'"),
])
def test_bad_design_files_are_one_line_errors(tmp_path, edit, message):
    import yaml

    data = rd.design_dict(rd.make_design(WORLDS[:2], load_robot(BASE), 3, 2, 1, seed=1))
    edit(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(InputError) as caught:
        rd.load_design(path)
    assert message in str(caught.value) and str(path) in str(caught.value)
    assert "\n" not in str(caught.value)


def test_the_extension_design_reuses_the_campaign_configurations(root):
    """design_more.yaml (campaign robots_more) deals design.yaml's own configurations to other
    buildings: same robots, bounds and base, so the two campaigns pool as one design."""
    from slam_predict.collect.robot_design import load_design

    main = load_design(root / "data" / "campaigns" / "robots" / "design.yaml")
    more = load_design(root / "data" / "campaigns" / "robots" / "design_more.yaml")
    assert more.configs == main.configs and more.bounds == main.bounds
    assert more.base == main.base and more.resolution_deg == main.resolution_deg
    assert not set(more.worlds) & set(main.worlds) and len(more.worlds) == 4
    assert all(len(set(c)) == main.points_per_world for c in more.worlds.values())


def test_the_configurations_design_adds_new_robots_to_the_same_buildings(root):
    """design_configs2.yaml (campaign robots_configs2): new configurations whose ids never
    clash with design.yaml's, within the same bounds, base robot and resolution, on the same
    21 buildings, each configuration on 3 of them, so that the campaigns pool."""
    from slam_predict.collect.robot_design import load_design

    main = load_design(root / "data" / "campaigns" / "robots" / "design.yaml")
    extra = load_design(root / "data" / "campaigns" / "robots" / "design_configs2.yaml")
    assert not set(extra.configs) & set(main.configs) and len(extra.configs) == 14
    assert extra.bounds == main.bounds and extra.base == main.base
    assert extra.resolution_deg == main.resolution_deg
    assert set(extra.worlds) == set(main.worlds)
    for factor, (low, high) in extra.bounds.items():
        assert all(low <= c[factor] <= high for c in extra.configs.values())
    dealt = [c for cs in extra.worlds.values() for c in cs]
    assert all(dealt.count(c) == 3 for c in extra.configs)
